#!/usr/bin/env bash
# Equal time for gradient-domain MLT (report the numbers in the issue note; nothing here is asserted): MLT's own
# image (`--strategies auto`), MLT's states through the gradient stage (mlt-gd: lt-mutate --stream - |
# lt-gradient --from-paths -, L2 and L1), GDMLT (gdmlt: the chains targeting the gradients, L2 and L1), and
# G-PT and gradient-domain path reusing (L2), the same time each, on veach-bidir (the crop around the egg
# against the scene's reference, as bench/memlt.sh) and on caustic-mirror (whole frame against a long BDPT
# reference made here first when OUT has none: REF_TIME seconds, default 900). SCENES="veach-bidir" runs one.
#   [REF_TIME=S] pipelines/bench/gdmlt.sh [SECONDS] [OUT]   (default 60 s, bench-gdmlt)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-gradient
seconds="${1:-60}"
out="${2:-bench-gdmlt}"
mkdir -p "$out"
methods="mlt mlt-gd mlt-gd-l1 gdmlt gdmlt-l1 gpt gdpr"

for scene in ${SCENES:-veach-bidir caustic-mirror}; do
  crop=()
  if [ "$scene" = veach-bidir ]; then
    ref="$root/scenes/veach-bidir/reference.exr"; crop=(--crop 480,540,320,260)
  else
    ref="$(reference_for "$scene" "$out")"
  fi
  bash "$root/pipelines/compare.sh" "$root/scenes/$scene/scene.xml" --time "$seconds" --methods "$methods" \
    --ref "$ref" "${crop[@]}" --out "$out/$scene"
  for m in mlt-gd gdmlt; do
    echo "== $scene, $m: the chains and the gradient stage"
    "$bin/lt-inspect" "$out/$scene/$m.chains.lts" | grep -E "^           (mutations|wall_seconds|startup_seconds|b) "
    "$bin/lt-inspect" "$out/$scene/$m.gradient.lts" | sed -n '/stat *run/,/own_seconds/p;/stat *shift/,/occluded/p'
  done
done
