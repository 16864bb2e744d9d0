#!/usr/bin/env bash
# Equal-time comparison of the chains with and without the direct split (lt-mutate --direct-samples, default 16,
# against -1): path-space MLT, PSSMLT and MMLT each way, for the same time, on cornell-box and veach-bidir (against
# their references) and on tiny-lamp, lamp-pool, door-ajar and caustic-mirror (against a long BDPT reference made here
# first when OUT has none: REF_TIME seconds, default 1800, on all cores). Report the numbers in the issue note; nothing
# here is asserted. SCENES="tiny-lamp lamp-pool" runs only those.
#   [REF_TIME=S] pipelines/bench/direct-split.sh [SECONDS] [OUT]   (default 60 s per method, OUT bench-direct-split)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-mutate
seconds="${1:-60}"
out="${2:-bench-direct-split}"
mkdir -p "$out"
methods="mlt mlt-nosplit pssmlt pssmlt-nosplit mmlt mmlt-nosplit"

for scene in ${SCENES:-cornell-box veach-bidir tiny-lamp lamp-pool door-ajar caustic-mirror}; do
  ref="$(REF_TIME="${REF_TIME:-1800}" reference_for "$scene" "$out")"
  bash "$root/pipelines/compare.sh" "$root/scenes/$scene/scene.xml" --time "$seconds" --methods "$methods" \
    --ref "$ref" --out "$out/$scene"
done

# How much of each image the direct part holds, and b's precision, from the files themselves.
for scene in ${SCENES:-cornell-box veach-bidir tiny-lamp lamp-pool door-ajar caustic-mirror}; do
  for m in $methods; do
    echo "== $scene, $m: $("$bin/lt-inspect" "$out/$scene/$m.lts" | grep -E "^ +(direct_share|b_relative_standard_error) " | tr -s ' ' | tr '\n' ' ')"
  done
done
