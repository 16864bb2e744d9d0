# Shared by the command-line tests (sourced, not run: CTest runs only *.sh):
#   source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"     with arguments BIN_DIR SOURCE_DIR
# Each check prints "ok: NAME" or "FAILED: NAME"; a script ends with `exit $fail`.
set -u
bin="$1"; src="$2"
fail=0
check() { if ! eval "$2"; then echo "FAILED: $1"; fail=1; else echo "ok: $1"; fi; }
# The first N bytes of a file as hex, for magic numbers (EXR 762f3101, PNG 89504e47).
magic() { head -c "$2" "$1" | od -An -tx1 | tr -d ' \n'; }
