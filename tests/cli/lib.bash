# Shared by the command-line tests (sourced, not run: CTest runs only *.sh):
#   source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"     with arguments BIN_DIR SOURCE_DIR
# Each check prints "ok: NAME" or "FAILED: NAME"; a script ends with `exit $fail`.
set -u
bin="$1"; src="$2"
fail=0
check() { if ! eval "$2"; then echo "FAILED: $1"; fail=1; else echo "ok: $1"; fi; }
# The first N bytes of a file as hex, for magic numbers (EXR 762f3101, PNG 89504e47).
magic() { head -c "$2" "$1" | od -An -tx1 | tr -d ' \n'; }

# Chunk payloads of a file as hex, except INFO and the STAT "run" table (they record the command line,
# the start time and how long the run took). Quiet when a reader stops early (grep -q).
chunks() { /usr/bin/python3 - "$1" 2>/dev/null <<'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
assert data[:4] == b'LTF\x01', 'bad magic'
pos, out = 12, []
while pos < len(data):
    tag = data[pos:pos+4].decode(); n, = struct.unpack_from('<Q', data, pos + 4)
    payload = data[pos+12:pos+12+n]
    if tag != 'INFO' and not (tag == 'STAT' and payload[:7] == struct.pack('<I', 3) + b'run'):
        out.append(tag + ':' + payload.hex())
    pos += 12 + n + 4
print('\n'.join(out))
PY
}
