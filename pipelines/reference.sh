#!/usr/bin/env bash
# A long BDPT render as a reference image for lt-error.
#   pipelines/reference.sh SCENE --time SECONDS -o REF.exr [more lt-seed options, e.g. --resolution 256x256]
# The seed defaults to 1000003, not lt-seed's 0: compare.sh runs every method with seed 0, and a reference
# from the same seed would share the compared BDPT run's samples and understate its error.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
usage() { echo "usage: $0 SCENE --time SECONDS -o REF.exr [lt-seed options]" >&2; exit 2; }
[ $# -ge 1 ] || usage
scene="$1"; shift
time=""; out=""; seed=1000003; extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time) time="$2"; shift 2 ;;
    -o) out="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    *) extra+=("$1"); shift ;;
  esac
done
[ -n "$time" ] && [ -n "$out" ] || usage
[ -x "$bin/lt-seed" ] || { echo "$0: build first (tests/run.sh or pipelines/quickstart.sh)" >&2; exit 1; }
tmp="${out%.exr}.lts"
"$bin/lt-seed" "$scene" --method bdpt --time "$time" --seed "$seed" -o "$tmp" "${extra[@]}"
"$bin/lt-image" "$tmp" -o "$out"
echo "reference: $out (buffer with its run statistics: $tmp)"
