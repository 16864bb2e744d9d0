#!/usr/bin/env bash
# Run one tool over a list of values of one option and tabulate error, time and efficiency against a
# reference.
#   pipelines/sweep.sh SCENE --ref REF.exr --option --max-depth --values 3,5,8 [--out DIR] [-- lt-seed options]
# Example: pipelines/sweep.sh scenes/cornell-box/scene.xml --ref scenes/cornell-box/reference.exr \
#            --option --max-depth --values 3,5,8 -- --method pt --spp 16 --resolution 256x256
# (the reference must have the resolution the runs have).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
usage() { echo "usage: $0 SCENE --ref REF.exr --option NAME --values V1,V2,... [--out DIR] [-- lt-seed options]" >&2; exit 2; }
[ $# -ge 1 ] || usage
scene="$1"; shift
ref=""; option=""; values=""; out=""; extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --ref) ref="$2"; shift 2 ;;
    --option) option="$2"; shift 2 ;;
    --values) values="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) usage ;;
  esac
done
[ -n "$ref" ] && [ -n "$option" ] && [ -n "$values" ] || usage
out="${out:-sweep-${option#--}}"
mkdir -p "$out"
files=()
IFS=',' read -r -a list <<<"$values"
for v in "${list[@]}"; do
  f="$out/${option#--}=$v.lts"
  echo "== $option $v"
  "$bin/lt-seed" "$scene" "$option" "$v" -o "$f" -q "${extra[@]}"
  files+=("$f")
done
"$bin/lt-error" "${files[@]}" --ref "$ref" --csv "$out/sweep.csv" | tee "$out/sweep.txt"
echo "table: $out/sweep.txt, $out/sweep.csv"
