#!/usr/bin/env bash
# What each reconstruction does to the image mean and what it costs in relMSE, on firefly-heavy gradient-domain
# renders at low sample counts: G-PT and path reusing (SPP samples a pixel, default 4, seeds 1 to SEEDS, default 3) on
# door-ajar (light through a door left ajar) and window-room (a sky with a sun through a window), unbounded depth, at
# 160x120, each reconstructed by L2, L1 as the papers define it (--mean free) and L1 with the primal's mean restored
# over 4, 8, 16, 32 and 64 pixels (--mean-scale; 16 is the default). Against a BDPT reference made here first when OUT has
# none (REF_TIME seconds, default 600). Prints, per scene, method and reconstruction, the relMSE and lt-error's
# scale (the factor that brings the image's mean to the reference's) of every seed, and lt-reconstruct's mean shift;
# nothing is asserted.
#   [REF_TIME=S] [SPP=N] [SEEDS=K] pipelines/bench/l1-mean.sh [OUT]     (default OUT bench-l1-mean)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-reconstruct
out="${1:-bench-l1-mean}"
spp="${SPP:-4}"
seeds="${SEEDS:-3}"
size=160x120
mkdir -p "$out"

for scene in door-ajar window-room; do
  xml="$root/scenes/$scene/scene.xml"
  ref="$(REF_TIME="${REF_TIME:-600}" reference_for "$scene" "$out" --resolution "$size" --max-depth -1 -q)"
  for method in gpt gdpr; do
    for seed in $(seq 1 "$seeds"); do
      g="$out/$scene-$method-$seed.gradient.lts"
      "$bin/lt-gradient" "$xml" --method "$method" --spp "$spp" --resolution "$size" --max-depth -1 --seed "$seed" \
        -o "$g" -q
      for r in "l2:--norm l2" "l1-free:--norm l1 --mean free" "l1-kept4:--norm l1 --mean-scale 4" \
        "l1-kept8:--norm l1 --mean-scale 8" "l1-kept16:--norm l1 --mean-scale 16" \
        "l1-kept32:--norm l1 --mean-scale 32" "l1-kept64:--norm l1 --mean-scale 64"; do
        # shellcheck disable=SC2086 # the options are words
        line=$("$bin/lt-reconstruct" "$g" ${r#*:} -o "$out/$scene-$method-${r%%:*}-$seed.lts" 2>&1 | grep -o "mean [^;]*")
        echo "$scene $method ${r%%:*} seed $seed: $line"
      done
    done
    for r in l2 l1-free l1-kept4 l1-kept8 l1-kept16 l1-kept32 l1-kept64; do
      "$bin/lt-error" "$out/$scene-$method-$r-"*.lts --ref "$ref" --json | python3 -c "
import json, sys
rows = json.load(sys.stdin)['rows']
print('== %s %s %s: relMSE %s, scale %s' % (sys.argv[1], sys.argv[2], sys.argv[3],
      ' '.join('%.4g' % r['error'] for r in rows), ' '.join('%.3f' % r['scale'] for r in rows)))" "$scene" "$method" "$r"
    done
  done
done
