#!/usr/bin/env bash
# Equal-time comparison for the gradient-domain estimators (report the numbers in the issue note; nothing
# here is asserted): path tracing, BDPT, G-PT and gradient-domain path reusing (tile 6), each gradient render
# reconstructed with L2 and with L1 (one render per estimator; each image is charged its reconstruction), for
# the same time each, on cornell-box, veach-mis and veach-bidir (whole frame against the scene's reference)
# and on door-ajar (against a long BDPT reference made here first when OUT has none: REF_TIME seconds,
# default 900). Then a tile-size sweep of path reusing on door-ajar (TILE_SECONDS each, default 30).
# SCENES="veach-mis door-ajar" runs only those.
#   [REF_TIME=S] [TILE_SECONDS=S] pipelines/bench/gradient.sh [SECONDS] [OUT]   (default 120 s, bench-gradient)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-gradient
seconds="${1:-120}"
out="${2:-bench-gradient}"
mkdir -p "$out"
methods="pt bdpt gpt gpt-l1 gdpr gdpr-l1"

for scene in ${SCENES:-cornell-box veach-mis veach-bidir door-ajar}; do
  ref="$(reference_for "$scene" "$out")"
  bash "$root/pipelines/compare.sh" "$root/scenes/$scene/scene.xml" --time "$seconds" --methods "$methods" \
    --ref "$ref" --out "$out/$scene"
  for m in gpt gdpr; do
    echo "== $scene, $m"
    "$bin/lt-inspect" "$out/$scene/$m.gradient.lts" | sed -n '/stat *shift/,/rr_survived/p'
  done
done

# Tile sizes: relMSE of the L2 reconstruction after the same time.
tiles="$out/tiles"
mkdir -p "$tiles"
ref="$root/scenes/door-ajar/reference.exr"; [ -f "$ref" ] || ref="$out/door-ajar-reference.exr"
if [ -f "$ref" ]; then
  for t in 2 4 6 8 12 16; do
    "$bin/lt-gradient" "$root/scenes/door-ajar/scene.xml" --method gdpr --tile "$t" --time "${TILE_SECONDS:-30}" \
      -o "$tiles/tile$t.gradient.lts" -q
    "$bin/lt-reconstruct" "$tiles/tile$t.gradient.lts" -o "$tiles/tile$t.lts" -q
  done
  "$bin/lt-error" "$tiles"/tile{2,4,6,8,12,16}.lts --ref "$ref" | grep -v SNAP | tee "$tiles/error.txt"
fi
