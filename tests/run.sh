#!/usr/bin/env bash
# Install what is missing, build (Release), run the whole test suite. Exits non-zero on any failure.
#   tests/run.sh                 # everything
#   BUILD_DIR=build-asan LT_SANITIZE=ON tests/run.sh   # with AddressSanitizer + UBSan
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
jobs="${JOBS:-$(nproc)}"

"$root/pipelines/install-deps.sh"

start=$(date +%s)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLT_SANITIZE="${LT_SANITIZE:-OFF}" >/dev/null
cmake --build "$build" -j "$jobs"
built=$(date +%s)
echo "run.sh: build took $((built - start)) s"

cd "$build"
ctest --output-on-failure -j "$jobs" --timeout 900
echo "run.sh: tests took $(($(date +%s) - built)) s"
