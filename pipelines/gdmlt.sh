#!/usr/bin/env bash
# Gradient-domain MLT (Lehtinen et al. 2013) in one command: the four stages in one pipe, as a user would chain
# them by hand:
#   lt-seed (seed paths) | lt-mutate --target gradient --stream - | lt-gradient --from-paths - | lt-reconstruct
# The snapshots of the gradient stage carry the pipeline's wall time (every stage starts at once), and
# lt-reconstruct reconstructs each, so `lt-error DIR/gdmlt.lts --ref REF` gives error against time.
#   pipelines/gdmlt.sh SCENE --time SECONDS [--out DIR] [--target gradient|luminance] [--norm l2|l1]
#                      [--seed-spp N] [--seed S] [-- options for every tool, e.g. --resolution 320x240]
# DIR (default gdmlt-SCENEDIR) receives gdmlt.lts (the reconstructed image and snapshots), gradient.lts (primal,
# dx, dy, direct and their snapshots), chains.lts (the chains' own image), seed.lts (the seed run's image).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
usage() { echo "usage: $0 SCENE --time SECONDS [--out DIR] [--target gradient|luminance] [--norm l2|l1] [--seed-spp N] [--seed S] [-- tool options]" >&2; exit 2; }
[ $# -ge 1 ] || usage
scene="$1"; shift
time=""; out=""; target=gradient; norm=l2; seedSpp=4; seed=0; extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time) time="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --target) target="$2"; shift 2 ;;
    --norm) norm="$2"; shift 2 ;;
    --seed-spp) seedSpp="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) usage ;;
  esac
done
[ -n "$time" ] || usage
[ -f "$scene" ] || { echo "$0: $scene: no such scene" >&2; exit 1; }
out="${out:-gdmlt-$(basename "$(dirname "$scene")")}"
mkdir -p "$out"

"$bin/lt-seed" "$scene" --spp "$seedSpp" --seed "$seed" -o "$out/seed.lts" --paths - -q "${extra[@]}" |
  "$bin/lt-mutate" "$scene" - --target "$target" --time "$time" --seed "$seed" --stream - -o "$out/chains.lts" -q \
    "${extra[@]}" |
  "$bin/lt-gradient" "$scene" --from-paths - --snapshots doubling -o - -q "${extra[@]}" |
  tee "$out/gradient.lts" |
  "$bin/lt-reconstruct" - --norm "$norm" -o "$out/gdmlt.lts" -q
"$bin/lt-image" "$out/gdmlt.lts" -o "$out/gdmlt.exr" --png "$out/gdmlt.png"
echo "$out/gdmlt.lts (and $out/gdmlt.png): the reconstructed image and its snapshots; lt-error $out/gdmlt.lts --ref REF"
"$bin/lt-inspect" "$out/gdmlt.lts" | grep -E "^snapshots" || true
