#!/usr/bin/env bash
# Writes the seed corpora of the fuzz harnesses (tests/fuzz/corpus/TARGET) and the scene harness's assets
# (tests/fuzz/assets): small valid files of each kind, the lt files and EXRs made by the tools, the meshes
# written here byte by byte. Run once after a format changes, then commit what it wrote. The inputs of fixed
# findings, tests/fuzz/corpus/TARGET/finding-*, are kept.
#   tests/fuzz/make_corpus.sh          (BUILD_DIR: a built lt, default build/)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
[ -x "$bin/lt-seed" ] || { echo "build first: cmake -S $root -B $root/build && cmake --build $root/build" >&2; exit 1; }
fuzz="$root/tests/fuzz"
corpus="$fuzz/corpus"
# Regression inputs of fixed findings (finding-*) stay; everything this script makes is made again.
find "$corpus" -type f ! -name 'finding-*' -delete 2>/dev/null || true
mkdir -p "$corpus"/{ltfile,gradient-input,scene,obj-loader,ply-loader,serialized-loader} "$fuzz/assets"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# --- meshes: one small quad (two triangles) in every layout the loaders read
python3 - "$corpus" "$fuzz/assets" <<'PY'
import struct, sys, zlib
corpus, assets = sys.argv[1], sys.argv[2]
P = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
N = [(0, 0, 1)] * 4
UV = [(0, 0), (1, 0), (1, 1), (0, 1)]
F = [(0, 1, 2), (0, 2, 3)]

def write(path, data):
    with open(path, 'wb') as f:
        f.write(data.encode() if isinstance(data, str) else data)

obj = ''.join('v %g %g %g\n' % p for p in P) + ''.join('vt %g %g\n' % t for t in UV) + \
      ''.join('vn %g %g %g\n' % n for n in N)
write(f'{corpus}/obj-loader/quad-vt-vn.obj', obj + 'f 1/1/1 2/2/2 3/3/3 4/4/4\n')
write(f'{corpus}/obj-loader/negative-indices.obj', obj + 'g quad\nusemtl none\nf -4 -3 -2\nf -4//-4 -2//-2 -1//-1\n')
write(f'{corpus}/obj-loader/positions-only.obj', ''.join('v %g %g %g\n' % p for p in P) + 'o a\nf 1 2 3\ns 1\nf 1 3 4\n')
write(f'{assets}/mesh.obj', obj + 'f 1/1/1 2/2/2 3/3/3\nf 1/1/1 3/3/3 4/4/4\n')

def ply_header(fmt, faces_type='uchar', extra=''):
    return ('ply\nformat %s 1.0\ncomment lt fuzz corpus\nelement vertex 4\nproperty float x\nproperty float y\n'
            'property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\n'
            'property float v\n%selement face 2\nproperty list %s int vertex_indices\nend_header\n'
            % (fmt, extra, faces_type))
ascii_body = ''.join('%g %g %g %g %g %g %g %g\n' % (p + n + t) for p, n, t in zip(P, N, UV)) + \
             ''.join('3 %d %d %d\n' % f for f in F)
write(f'{corpus}/ply-loader/ascii.ply', ply_header('ascii') + ascii_body)
for endian, name in (('<', 'binary_little_endian'), ('>', 'binary_big_endian')):
    body = b''.join(struct.pack(endian + '8f', *(p + n + t)) for p, n, t in zip(P, N, UV))
    body += b''.join(struct.pack(endian + 'B3i', 3, *f) for f in F)
    write(f'{corpus}/ply-loader/{name}.ply', ply_header(name).encode() + body)
quad = 'ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n' \
       'property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n' \
       'property list uint8 uint32 vertex_indices\nend_header\n' + \
       ''.join('%g %g %g 255 0 0\n' % p for p in P) + '4 0 1 2 3\n'
write(f'{corpus}/ply-loader/quad-doubles-colors.ply', quad)
write(f'{assets}/mesh.ply', ply_header('ascii') + ascii_body)

def serialized_mesh(version, flags, doubles):
    payload = struct.pack('<I', flags | (0x2000 if doubles else 0x1000))
    if version == 4: payload += b'quad\0'
    payload += struct.pack('<QQ', 4, 2)
    fmt = '<%dd' if doubles else '<%df'
    arrays = [sum(P, ())]
    if flags & 1: arrays.append(sum(N, ()))
    if flags & 2: arrays.append(sum(UV, ()))
    if flags & 8: arrays.append((1, 0, 0) * 4)
    for a in arrays: payload += struct.pack(fmt % len(a), *a)
    payload += struct.pack('<6I', *sum(F, ()))
    return struct.pack('<HH', 0x041C, version) + zlib.compress(payload, 9)

def serialized_file(version, meshes):
    out, offsets = b'', []
    for m in meshes:
        offsets.append(len(out)); out += m
    out += b''.join(struct.pack('<Q' if version == 4 else '<I', o) for o in offsets)
    return out + struct.pack('<I', len(meshes))

for version in (3, 4):
    write(f'{corpus}/serialized-loader/v{version}-two-meshes.serialized',
          serialized_file(version, [serialized_mesh(version, 1 | 2, False), serialized_mesh(version, 8, True)]))
write(f'{corpus}/serialized-loader/v4-face-normals.serialized', serialized_file(4, [serialized_mesh(4, 0x10 | 1, False)]))
write(f'{assets}/mesh.serialized', serialized_file(4, [serialized_mesh(4, 1 | 2, False), serialized_mesh(4, 0, True)]))
PY

# --- the scene harness's assets: a texture and an included file
"$bin/lt-seed" "$root/scenes/cornell-box/scene.xml" --resolution 4x4 --spp 1 -q -o "$work/texture.lts"
"$bin/lt-image" "$work/texture.lts" -o "$fuzz/assets/texture.exr" --png "$fuzz/assets/texture.png" >/dev/null
cat > "$fuzz/assets/included.xml" <<'XML'
<scene version="0.6.0">
	<bsdf type="diffuse" id="included-white"/>
</scene>
XML

# --- scenes: every scene of scenes/ (their meshes are not in the sandbox: the missing-file path), and scenes
# built on the assets
for s in "$root"/scenes/*/scene.xml; do
  name=$(basename "$(dirname "$s")")
  cp "$s" "$corpus/scene/$name.xml"
done
cat > "$corpus/scene/assets-0.6.xml" <<'XML'
<?xml version="1.0" encoding="utf-8"?>
<scene version="0.6.0">
	<default name="spp" value="4"/>
	<integrator type="path"><integer name="maxDepth" value="5"/></integrator>
	<include filename="included.xml"/>
	<sensor type="perspective">
		<float name="fov" value="45"/>
		<transform name="toWorld"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
		<sampler type="independent"><integer name="sampleCount" value="$spp"/></sampler>
		<film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
	</sensor>
	<bsdf type="roughplastic" id="plastic">
		<float name="alpha" value="0.2"/>
		<texture type="bitmap" name="diffuseReflectance"><string name="filename" value="texture.png"/></texture>
	</bsdf>
	<shape type="obj"><string name="filename" value="mesh.obj"/><ref id="plastic"/></shape>
	<shape type="ply"><string name="filename" value="mesh.ply"/><ref id="included-white"/>
		<transform name="toWorld"><scale value="2"/><rotate y="1" angle="30"/><translate x="1"/></transform>
	</shape>
	<shape type="serialized"><string name="filename" value="mesh.serialized"/><integer name="shapeIndex" value="1"/>
		<bsdf type="dielectric"><float name="intIOR" value="1.5"/></bsdf>
	</shape>
	<shape type="sphere"><point name="center" x="0" y="0" z="-2"/><float name="radius" value="0.5"/>
		<bsdf type="bumpmap"><texture type="scale"><float name="scale" value="0.1"/>
			<texture type="bitmap"><string name="filename" value="texture.exr"/></texture></texture>
			<bsdf type="conductor"><string name="material" value="Cu"/></bsdf></bsdf>
	</shape>
	<shape type="rectangle"><emitter type="area"><spectrum name="radiance" value="400:1, 700:2"/></emitter></shape>
	<emitter type="sunsky"><float name="hour" value="16"/><integer name="resolution" value="16"/></emitter>
</scene>
XML
cat > "$corpus/scene/assets-3.xml" <<'XML'
<scene version="3.0.0">
	<default name="res" value="8"/>
	<integrator type="volpath"><integer name="max_depth" value="4"/></integrator>
	<sensor type="thinlens">
		<float name="aperture_radius" value="0.1"/><float name="focus_distance" value="4"/>
		<transform name="to_world"><lookat origin="0, 2, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
		<film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/></film>
	</sensor>
	<bsdf type="twosided" id="white"><bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.7, 0.6"/></bsdf></bsdf>
	<shape type="cube"><ref id="white"/><transform name="to_world"><scale value="0.5"/></transform></shape>
	<shape type="disk"><bsdf type="roughconductor"><string name="distribution" value="ggx"/></bsdf></shape>
	<emitter type="point"><point name="position" value="0, 3, 0"/><rgb name="intensity" value="10"/></emitter>
	<emitter type="envmap"><string name="filename" value="texture.exr"/></emitter>
</scene>
XML

# --- lt files: a buffer with snapshots, seed paths, a chain-state stream, gradients, a reconstruction's stats
scene="$root/scenes/cornell-box/scene.xml"
"$bin/lt-seed" "$scene" --resolution 4x4 --spp 2 --snapshot-samples 1 -q -o "$corpus/ltfile/seed-buffer.lts" \
  --paths "$corpus/ltfile/seed-paths.ltp" --max-paths 6
"$bin/lt-mutate" "$scene" --resolution 4x4 --mutations 64 --chains 2 --startup-samples 16 -q \
  -o "$work/mutate.lts" --stream "$corpus/ltfile/chain-states.ltp"
"$bin/lt-mutate" "$scene" --space multiplexed --resolution 4x4 --mutations 64 --chains 2 --startup-samples 16 -q \
  -o "$corpus/ltfile/mmlt-buffer.lts"
"$bin/lt-gradient" "$scene" --method gpt --resolution 4x4 --spp 1 -q -o "$corpus/gradient-input/gpt.lts"
"$bin/lt-reconstruct" "$corpus/gradient-input/gpt.lts" -q -o "$corpus/ltfile/reconstructed.lts"
cp "$corpus/gradient-input/gpt.lts" "$corpus/ltfile/gpt.lts"
"$bin/lt-image" "$corpus/gradient-input/gpt.lts" -o "$corpus/gradient-input/gpt.exr" >/dev/null
"$bin/lt-seed" "$scene" --resolution 4x4 --spp 1 -q -o - > "$corpus/gradient-input/primal.lts"
ls -l "$corpus"/* "$fuzz/assets"
