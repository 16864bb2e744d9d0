#!/usr/bin/env bash
# Equal-time comparison for the portal perturbation (report the numbers in the issue note; nothing here is
# asserted), after Otsu et al.'s Sec. 5: on every scene of SCENES (default window-room: a sky through a
# window; portal-room: an area light beyond a small window; door-ajar: a room lit indirectly through a door
# opening, the paper's AJAR DOOR case), SECONDS each, BDPT, PSSMLT, path-space MLT with the lens
# perturbation alone (mlt-lens: bidirectional : lens = 1 : 1, the paper's baseline), with lens and portal
# (portal: bidirectional : (lens : portal = 1 : 1) = 1 : 1, the paper's method) and MEMLT. relMSE against a
# long BDPT reference made here first when OUT has none (REF_TIME seconds, default 900), for the whole frame
# and for the scene's two regions (lit directly through the portal, lit only indirectly; crops below).
# Then the paper's Fig. 4 on three-planes: one chain's image-plane position every 500 mutations (500
# points) and its vertical trace, lens against portal (OUT/trace.png).
#   [REF_TIME=S] [SCENES="window-room portal-room"] [METHODS="mlt-lens portal"] pipelines/bench/portal.sh [SECONDS] [OUT]
#   (default 60 s, bench-portal; SCENES="" skips the comparison, TRACE=0 the trace plot)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-mutate
seconds="${1:-60}"
out="${2:-bench-portal}"
mkdir -p "$out"
methods="${METHODS:-bdpt pssmlt mlt-lens portal memlt}"

# Regions (X,Y,W,H at the scenes' own resolution): lit directly through the portal, then lit only indirectly.
regions() {
  case "$1" in
    window-room) echo "110,150,70,25 20,40,60,70" ;; # the sunlit floor patch; the left wall and the ball in shade
    portal-room) echo "120,205,70,30 10,20,60,60" ;;  # the floor patch the window lights; the upper left wall
    door-ajar) echo "116,50,12,40 10,10,40,30" ;;     # the strip of direct light at the right edge; the far wall
    *) echo "" ;;
  esac
}

for scene in ${SCENES-window-room portal-room door-ajar}; do
  ref="$(reference_for "$scene" "$out")"
  bash "$root/pipelines/compare.sh" "$root/scenes/$scene/scene.xml" --time "$seconds" --methods "$methods" \
    --ref "$ref" --out "$out/$scene" > /dev/null
  files=()
  for m in $methods; do files+=("$out/$scene/$m.lts"); done
  {
    echo "== $scene: whole frame"
    "$bin/lt-error" "${files[@]}" --ref "$ref" | grep -v '^SNAP'
    for crop in $(regions "$scene"); do
      echo "== $scene: region $crop"
      "$bin/lt-error" "${files[@]}" --ref "$ref" --crop "$crop" | grep -v '^SNAP'
    done
    for m in mlt-lens portal; do
      [ -f "$out/$scene/$m.lts" ] || continue
      echo "== $scene: $m strategies"
      "$bin/lt-inspect" "$out/$scene/$m.lts" | sed -n '/stat *strategies/,/^$/p'
    done
  } | tee "$out/$scene/summary.txt"
done

[ "${TRACE:-1}" = 0 ] && exit 0
# Fig. 4 (c, d): two chains of 250 000 mutations each, every 500th state dumped; chain 0's raster positions.
trace="$out/trace"
mkdir -p "$trace"
for mix in lens portal; do
  strategies=bidirectional,lens
  [ "$mix" = portal ] && strategies=bidirectional:2,lens,portal
  "$bin/lt-mutate" "$root/scenes/three-planes/scene.xml" --strategies "$strategies" --chains 2 --threads 1 \
    --mutations 500000 --seed 1 -o "$trace/$mix.lts" --dump-paths "$trace/$mix.ltp" --dump-every 500 -q
  "$bin/lt-inspect" "$trace/$mix.ltp" --paths --json --limit 100000 > "$trace/$mix.json"
done
/usr/bin/python3 - "$trace" <<'PY'
import json, os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
trace = sys.argv[1]
fig, axes = plt.subplots(2, 2, figsize=(9, 8))
for col, mix in enumerate(["lens", "portal"]):
    records = json.load(open(os.path.join(trace, mix + ".json")))["paths"]["records"]
    pts = sorted((r["rng_offset"], r["raster"]) for r in records if r["rng_stream"] == 0)
    xs = [p[1][0] / 256 for p in pts]
    ys = [p[1][1] / 256 for p in pts]
    ax = axes[0][col]
    ax.plot(xs, ys, "-o", markersize=2, linewidth=0.3)
    ax.set_xlim(0, 1); ax.set_ylim(1, 0); ax.set_aspect("equal")
    ax.set_title("%s: chain 0 every 500 mutations (%d points)" % (mix, len(xs)))
    axes[1][col].plot(range(min(200, len(ys))), ys[:200], linewidth=0.8)
    axes[1][col].set_ylim(0, 1); axes[1][col].set_xlabel("sample (x 500 mutations)"); axes[1][col].set_ylabel("y")
fig.tight_layout()
tmp = os.path.join(trace, ".trace.partial.png")
fig.savefig(tmp, dpi=120); os.replace(tmp, os.path.join(os.path.dirname(trace), "trace.png"))
PY
echo "results in $out/: SCENE/summary.txt, SCENE/figure.png, SCENE/error.png, trace.png"
