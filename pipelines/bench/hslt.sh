#!/usr/bin/env bash
# Equal-time comparison for the half-vector space mutation (report the numbers in the issue note; nothing
# here is asserted): BDPT, PSSMLT, path-space MLT with Veach's perturbations (mlt: --strategies auto),
# MEMLT (bidirectional + manifold) and HSLT (bidirectional + hslt), SECONDS each, on veach-mis and
# veach-bidir (whole frame against the scene's reference) and on glossy-rings (against a long BDPT
# reference made here first when OUT has none: REF_TIME seconds, default 900). Then on glossy-rings, SWEEP
# seconds each (default 30): HSLT's gamma (0.03, 0.1, 0.3, 1) and its image-plane stratification off
# (--hslt-stratify 0) against on (0.02); SWEEP=0 leaves the sweep out. SCENES="glossy-rings" runs only those.
#   [REF_TIME=S] [SWEEP=S] pipelines/bench/hslt.sh [SECONDS] [OUT]   (default 60 s, bench-hslt)
# With AUTO=1, only the question whether `auto` should take hslt, SECONDS each on every scene of SCENES:
# auto's own mix (mlt) against the same mix with hslt added, and on glossy-rings HSLT's jumps on and off
# (bidirectional + hslt), in OUT/auto/SCENE.
#   AUTO=1 [SCENES=...] pipelines/bench/hslt.sh 120 bench-hslt
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-mutate
seconds="${1:-60}"
out="${2:-bench-hslt}"
mkdir -p "$out"
methods="bdpt pssmlt mlt memlt hslt"

if [ -n "${AUTO:-}" ]; then
  for scene in ${SCENES:-glossy-rings veach-mis veach-bidir}; do
    ref="$(reference_for "$scene" "$out")"
    dir="$out/auto/$scene"
    mkdir -p "$dir"
    xml="$root/scenes/$scene/scene.xml"
    "$bin/lt-mutate" "$xml" --strategies auto --time "$seconds" --snapshots doubling -o "$dir/auto.lts" 2> "$dir/auto.log"
    # auto's mix as it was chosen (INFO strategies), with hslt added at weight 1.
    mix="$("$bin/lt-inspect" "$dir/auto.lts" | sed -n 's/.*strategies=\[\(.*\)\].*/\1/p' |
      grep -o '"name":"[a-z-]*"' | cut -d'"' -f4 | paste -sd, -)"
    "$bin/lt-mutate" "$xml" --strategies "$mix,hslt" --time "$seconds" --snapshots doubling -o "$dir/auto-hslt.lts" \
      2> "$dir/auto-hslt.log"
    files=("$dir/auto.lts" "$dir/auto-hslt.lts")
    if [ "$scene" = glossy-rings ]; then
      for j in on off; do
        "$bin/lt-mutate" "$xml" --strategies bidirectional,hslt --hslt-jumps "$j" --time "$seconds" --snapshots doubling \
          -o "$dir/hslt-jumps-$j.lts" 2> "$dir/hslt-jumps-$j.log"
        files+=("$dir/hslt-jumps-$j.lts")
      done
    fi
    echo "== $scene: auto = $mix"
    "$bin/lt-error" "${files[@]}" --ref "$ref" | tee "$dir/error.txt"
  done
  exit 0
fi

for scene in ${SCENES:-veach-mis glossy-rings veach-bidir}; do
  ref="$(reference_for "$scene" "$out")"
  bash "$root/pipelines/compare.sh" "$root/scenes/$scene/scene.xml" --time "$seconds" --methods "$methods" \
    --ref "$ref" --out "$out/$scene"
  echo "== $scene, hslt"
  "$bin/lt-inspect" "$out/$scene/hslt.lts" | sed -n '/walks.hslt/,/^$/p' | head -20
done

# gamma and stratification on glossy-rings: relMSE after the same time.
[ "${SWEEP:-30}" = 0 ] && exit 0
sweep="$out/sweep"
mkdir -p "$sweep"
ref="$(reference glossy-rings)"
for g in 0.03 0.1 0.3 1; do
  "$bin/lt-mutate" "$root/scenes/glossy-rings/scene.xml" --strategies bidirectional,hslt --hslt-gamma "$g" \
    --time "${SWEEP:-30}" -o "$sweep/gamma$g.lts" -q
done
"$bin/lt-mutate" "$root/scenes/glossy-rings/scene.xml" --strategies bidirectional,hslt --hslt-stratify 0 \
  --time "${SWEEP:-30}" -o "$sweep/stratify0.lts" -q
"$bin/lt-error" "$sweep"/gamma{0.03,0.1,0.3,1}.lts "$sweep/stratify0.lts" --ref "$ref" | grep -v SNAP | tee "$sweep/error.txt"
