#!/usr/bin/env bash
# Run one tool over a list of values of one option and tabulate error, time and efficiency against a
# reference; for lt-mutate also each run's per-strategy acceptance (and walk figures).
#   pipelines/sweep.sh SCENE --ref REF.exr --option --max-depth --values 3,5,8 [--tool lt-seed|lt-mutate]
#                      [--out DIR] [-- tool options]
# Example: pipelines/sweep.sh scenes/cornell-box/scene.xml --ref scenes/cornell-box/reference.exr \
#            --option --max-depth --values 3,5,8 -- --method pt --spp 16 --resolution 256x256
#          pipelines/sweep.sh scenes/caustic-mirror/scene.xml --ref REF.exr --tool lt-mutate \
#            --option --lambda --values 10,30,50,150,500 -- --strategies bidirectional,manifold --time 30
# (the reference must have the resolution the runs have).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
usage() { echo "usage: $0 SCENE --ref REF.exr --option NAME --values V1,V2,... [--tool lt-seed|lt-mutate] [--out DIR] [-- tool options]" >&2; exit 2; }
[ $# -ge 1 ] || usage
scene="$1"; shift
ref=""; option=""; values=""; out=""; tool=lt-seed; extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --ref) ref="$2"; shift 2 ;;
    --option) option="$2"; shift 2 ;;
    --values) values="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --tool) tool="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) usage ;;
  esac
done
[ -n "$ref" ] && [ -n "$option" ] && [ -n "$values" ] || usage
case "$tool" in lt-seed|lt-mutate) ;; *) echo "$0: --tool must be lt-seed or lt-mutate, got '$tool'" >&2; exit 2 ;; esac
out="${out:-sweep-${option#--}}"
mkdir -p "$out"
files=()
IFS=',' read -r -a list <<<"$values"
for v in "${list[@]}"; do
  f="$out/${option#--}=$v.lts"
  echo "== $option $v"
  "$bin/$tool" "$scene" "$option" "$v" -o "$f" -q "${extra[@]}"
  files+=("$f")
done
"$bin/lt-error" "${files[@]}" --ref "$ref" --csv "$out/sweep.csv" | tee "$out/sweep.txt"
if [ "$tool" = lt-mutate ]; then
  for f in "${files[@]}"; do
    echo "== $(basename "$f" .lts): acceptance and rejections per strategy"
    "$bin/lt-inspect" "$f" | sed -n '/^stat *strategies/,$p' | tee -a "$out/sweep.txt"
  done
fi
echo "table: $out/sweep.txt, $out/sweep.csv"
