#!/usr/bin/env bash
# Do methods agree region by region? Independent runs of each method (seeds FIRST..FIRST+RUNS-1, FIRST 1
# unless --first-seed says otherwise; the same time each),
# and for every crop the ratio of a run's mean over the crop to the reference's, averaged over the runs
# with its standard error: a ratio more than ~3 standard errors from 1 is a bias in that region (or a
# wrong reference), not noise. The way to settle "the chains disagree with BDPT on this object".
#   pipelines/regions.sh SCENE --time SECONDS --runs N --methods "bdpt mlt mmlt" --ref REF.exr
#                        --crop X,Y,W,H [--crop ...] [--out DIR] [--first-seed N] [-- options for every tool]
# --first-seed gives runs independent of an earlier call's, to check a suspicious ratio on fresh seeds.
# Methods: pipelines/lib/methods.bash. The reference should be far less noisy than one run (render it
# with pipelines/reference.sh); the table shows its crop means so that can be checked.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
usage() { echo "usage: $0 SCENE --time SECONDS --runs N --methods \"bdpt mlt mmlt\" --ref REF.exr --crop X,Y,W,H [--crop ...] [--out DIR] [--first-seed N] [-- tool options]" >&2; exit 2; }
[ $# -ge 1 ] || usage
scene="$1"; shift
time=""; runs=""; methods=""; ref=""; crops=(); out=""; first=1; extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time) time="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --methods) methods="$2"; shift 2 ;;
    --ref) ref="$2"; shift 2 ;;
    --crop) crops+=("$2"); shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --first-seed) first="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) usage ;;
  esac
done
[ -n "$time" ] && [ -n "$runs" ] && [ -n "$methods" ] && [ -n "$ref" ] && [ ${#crops[@]} -gt 0 ] || usage
[ "$runs" -ge 2 ] 2>/dev/null || { echo "$0: --runs must be at least 2 (the spread of the runs is the error)" >&2; exit 2; }
[ "$first" -ge 0 ] 2>/dev/null || { echo "$0: --first-seed must be a non-negative integer, got '$first'" >&2; exit 2; }
[ -f "$scene" ] || { echo "$0: $scene: no such scene" >&2; exit 1; }
[ -f "$ref" ] || { echo "$0: $ref: no such reference" >&2; exit 1; }
out="${out:-regions-$(basename "$(dirname "$scene")")}"
mkdir -p "$out"
source "$root/pipelines/lib/methods.bash"
check_methods $methods || exit 1

# lt-error's scale column is (reference crop mean) / (image crop mean): its inverse is the ratio wanted.
rows="$out/ratios.txt"
: > "$rows"
for m in $methods; do
  for seed in $(seq "$first" $((first + runs - 1))); do
    file="$out/$m-$seed.lts"
    echo "== $m, seed $seed ($runs runs from $first), $time s"
    render_method "$m" "$file" "$time" "$seed" "${extra[@]}"
    for c in "${crops[@]}"; do
      "$bin/lt-error" "$file" --ref "$ref" --crop "$c" --csv "$out/.row.csv" > /dev/null
      scale=$(/usr/bin/python3 -c 'import csv, sys; print(*[r["scale"] for r in csv.DictReader(open(sys.argv[1])) if r["label"] == "BUFR"])' "$out/.row.csv")
      echo "$m $c $seed $scale" >> "$rows"
    done
  done
done

rm -f "$out/.row.csv"
/usr/bin/python3 - "$rows" <<'PY' | tee "$out/regions.txt"
import sys, math, collections
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    m, crop, seed, scale = line.split()
    runs[(m, crop)].append(1 / float(scale) if float(scale) > 0 else float("nan"))
print(f"{'method':8s} {'crop':18s} {'runs':>4s} {'mean ratio to ref':>18s} {'std. error':>10s} {'z':>7s}")
for (m, crop), r in runs.items():
    n = len(r); mean = sum(r) / n
    se = math.sqrt(sum((x - mean) ** 2 for x in r) / (n - 1) / n)
    z = (mean - 1) / se if se > 0 else float("nan")
    print(f"{m:8s} {crop:18s} {n:4d} {mean:18.4f} {se:10.4f} {z:7.2f}")
PY
echo "results in $out/: regions.txt, ratios.txt (one row per run and crop), the runs' .lts files"
