#!/usr/bin/env bash
# Equal-time comparison for MEMLT (report the numbers in the issue note; nothing here is asserted): BDPT,
# PSSMLT, path-space MLT with Veach's perturbations (mlt: --strategies auto) and MEMLT (bidirectional +
# manifold) for the same time each, on veach-bidir (error in the crop around the glass egg and its
# caustic, against the scene's reference), on caustic-mirror and on glossy-caustic (its glossy twin: the
# manifold perturbation's offset manifolds), each whole frame against a long BDPT reference made here
# first when OUT has none: REF_TIME seconds, default 1800, on all cores. SCENES=glossy-caustic runs only
# that one (any of veach-bidir caustic-mirror glossy-caustic).
#   [REF_TIME=S] pipelines/bench/memlt.sh [SECONDS] [OUT]   (default 60 s per method, OUT bench-memlt)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-mutate
seconds="${1:-60}"
out="${2:-bench-memlt}"
mkdir -p "$out"
methods="bdpt pssmlt mlt memlt"

scenes="${SCENES:-veach-bidir caustic-mirror glossy-caustic}"
for scene in $scenes; do
  if [ "$scene" = veach-bidir ]; then
    bash "$root/pipelines/compare.sh" "$root/scenes/veach-bidir/scene.xml" --time "$seconds" --methods "$methods" \
      --ref "$root/scenes/veach-bidir/reference.exr" --crop 480,540,320,260 --out "$out/veach-bidir"
    continue
  fi
  ref="$(REF_TIME="${REF_TIME:-1800}" reference_for "$scene" "$out")"
  bash "$root/pipelines/compare.sh" "$root/scenes/$scene/scene.xml" --time "$seconds" --methods "$methods" \
    --ref "$ref" --out "$out/$scene"
done

# Each chain run's rejection table and walk figures, from the files themselves.
for scene in $scenes; do
  for m in mlt memlt; do
    echo "== $scene, $m"
    "$bin/lt-inspect" "$out/$scene/$m.lts" | sed -n '/strategies/,$p' | head -24
  done
done
