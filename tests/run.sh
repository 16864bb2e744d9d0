#!/usr/bin/env bash
# Install what is missing, build (Release), run the whole test suite. Exits non-zero on any failure.
#   tests/run.sh              everything, in build/ (BUILD_DIR)
#   tests/run.sh --sanitize   clang with AddressSanitizer + UBSan and the libFuzzer harnesses (-DLT_FUZZ=ON), in
#                             build-sanitize/ (BUILD_DIR): the fast part of the suite (the [slow] and [long]
#                             statistical tests left out) and each fuzz harness for LT_FUZZ_SECONDS (60) on its corpus
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${JOBS:-$(nproc)}"
sanitize=0
case "${1:-}" in
  "") ;;
  --sanitize) sanitize=1 ;;
  *) echo "usage: tests/run.sh [--sanitize]" >&2; exit 2 ;;
esac

"$root/pipelines/install-deps.sh"

start=$(date +%s)
if ((sanitize)); then
  build="${BUILD_DIR:-$root/build-sanitize}"
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLT_FUZZ=ON \
    -DLT_FUZZ_SECONDS="${LT_FUZZ_SECONDS:-60}" >/dev/null
  # A sanitizer report ends the process with an error; a leak is a failure too.
  export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
else
  build="${BUILD_DIR:-$root/build}"
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j "$jobs"
built=$(date +%s)
echo "run.sh: build took $((built - start)) s"

cd "$build"
ctest --output-on-failure -j "$jobs" --timeout 900
echo "run.sh: tests took $(($(date +%s) - built)) s"
