"""PFM to EXR: python3 pfm_to_exr.py IN.pfm OUT.exr

Tungsten built against Debian's OpenEXR 3 writes its HDR image only as PFM (its CMake looks for OpenEXR 2's
IlmImf); lt-error reads EXR. The output is an uncompressed scanline EXR with FLOAT channels B, G, R (the
simplest file the format allows), written with the standard library alone.
"""
import struct
import sys

src, dst = sys.argv[1], sys.argv[2]
data = open(src, "rb").read()
parts, pos = [], 0
while len(parts) < 4:  # "PF", width, height, scale: whitespace-separated tokens before the raster
    while data[pos:pos + 1].isspace(): pos += 1
    end = pos
    while not data[end:end + 1].isspace(): end += 1
    parts.append(data[pos:end].decode()); pos = end
pos += 1
assert parts[0] == "PF", "not an RGB PFM"
w, h, scale = int(parts[1]), int(parts[2]), float(parts[3])
px = struct.unpack(("<" if scale < 0 else ">") + f"{w * h * 3}f", data[pos:pos + w * h * 12])
def attr(name, kind, payload): return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(payload)) + payload
chlist = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "BGR") + b"\0"
box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
header = (struct.pack("<ii", 20000630, 2) + attr("channels", "chlist", chlist) + attr("compression", "compression", b"\0")
          + attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0")
          + attr("pixelAspectRatio", "float", struct.pack("<f", 1)) + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0))
          + attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")
blocks, offset = [], len(header) + 8 * h
for y in range(h):  # EXR rows top to bottom; PFM rows bottom to top
    row = (h - 1 - y) * w * 3
    line = b"".join(struct.pack(f"<{w}f", *px[row + c::3][:w]) for c in (2, 1, 0))
    blocks.append(struct.pack("<ii", y, len(line)) + line)
offsets = []
for b in blocks: offsets.append(offset); offset += len(b)
open(dst, "wb").write(header + struct.pack(f"<{h}Q", *offsets) + b"".join(blocks))
