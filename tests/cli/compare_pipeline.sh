#!/usr/bin/env bash
# pipelines/compare.sh and reference.sh end to end on a tiny scene: images, error table, plot, figure;
# a method without its tool is refused by name.
#   compare_pipeline.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
export BUILD_DIR="$(dirname "$bin")"
scene="$src/tests/cli/tiny_box.xml"

bash "$src/pipelines/reference.sh" "$scene" --time 1 -o "$tmp/ref.exr" > /dev/null 2>&1
check "reference.sh writes an EXR" '[ "$(magic "$tmp/ref.exr" 4)" = "762f3101" ]'
bash "$src/pipelines/compare.sh" "$scene" --time 1 --methods "bdpt mmlt" --ref "$tmp/ref.exr" --crop 2,2,8,8 --out "$tmp/cmp" > "$tmp/log" 2>&1; code=$?
check "compare.sh: exit 0" '[ $code -eq 0 ]'
check "compare.sh: images of both methods (lt-seed and lt-mutate)" '[ -s "$tmp/cmp/bdpt.exr" ] && [ -s "$tmp/cmp/mmlt.png" ]'
check "compare.sh: error table and CSV" 'grep -q relMSE "$tmp/cmp/error.txt" && [ "$(grep -c "BUFR" "$tmp/cmp/error.csv")" -eq 2 ]'
check "compare.sh: plot and figure are PNGs" '[ "$(magic "$tmp/cmp/error.png" 4)" = "89504e47" ] && [ "$(magic "$tmp/cmp/figure.png" 4)" = "89504e47" ]'
# 2 s: snapshots are taken at the end of a pass, and path reusing stops within a pass at its time limit, so a
# 1 s run may end before any pass ends after the first snapshot time (1 s).
bash "$src/pipelines/compare.sh" "$scene" --time 2 --methods "gpt gdpr gdpr-l1" --ref "$tmp/ref.exr" --out "$tmp/grad" > "$tmp/glog" 2>&1; code=$?
check "compare.sh gpt gdpr gdpr-l1: images, one gradient render per estimator, reconstructed snapshots measured" '[ $code -eq 0 ] &&
  [ -s "$tmp/grad/gpt.png" ] && [ -s "$tmp/grad/gdpr-l1.exr" ] && [ -s "$tmp/grad/gpt.gradient.lts" ] &&
  [ -s "$tmp/grad/gdpr.gradient.lts" ] &&
  grep -q "gdpr-l1.lts *SNAP" "$tmp/grad/error.txt"' || cat "$tmp/glog"
out=$(bash "$src/pipelines/compare.sh" "$scene" --time 1 --methods "pt portals" --out "$tmp/cmp2" 2>&1); code=$?
check "compare.sh: an unknown method is refused by name, before rendering" \
    '[ $code -ne 0 ] && echo "$out" | grep -q "unknown method .portals." && [ ! -e "$tmp/cmp2/pt.lts" ]'
bash "$src/pipelines/regions.sh" "$scene" --time 1 --runs 2 --methods "bdpt mmlt" --ref "$tmp/ref.exr" --crop 0,0,8,8 \
    --crop 4,4,8,8 --out "$tmp/reg" > "$tmp/reglog" 2>&1; code=$?
check "regions.sh: exit 0, a row per method and crop with the ratio to the reference" '[ $code -eq 0 ] &&
  [ "$(grep -Ec "^(bdpt|mmlt) +[0-9]+,[0-9]+,8,8 +2 +[0-9.]+ +[0-9.]+" "$tmp/reg/regions.txt")" -eq 4 ]' || cat "$tmp/reglog"
out=$(bash "$src/pipelines/regions.sh" "$scene" --time 1 --runs 1 --methods bdpt --ref "$tmp/ref.exr" --crop 0,0,8,8 2>&1); code=$?
check "regions.sh: one run is refused (no spread to measure)" '[ $code -ne 0 ] && echo "$out" | grep -q "at least 2"'
bash "$src/pipelines/sweep.sh" "$scene" --ref "$tmp/ref.exr" --option --max-depth --values 1,3 --out "$tmp/sw" -- --spp 2 > "$tmp/swlog" 2>&1; code=$?
check "sweep.sh: exit 0, a row per value" '[ $code -eq 0 ] && grep -q "max-depth=1.lts" "$tmp/sw/sweep.txt" && grep -q "max-depth=3.lts" "$tmp/sw/sweep.txt"'
# maxDepth 1 sees only the light: the rest of the box is black, so its error must be the larger one.
e1=$(awk '$1 ~ /max-depth=1/ { print $5 }' "$tmp/sw/sweep.txt"); e3=$(awk '$1 ~ /max-depth=3/ { print $5 }' "$tmp/sw/sweep.txt")
check "sweep.sh: depth 1 misses the indirect light ($e1 vs $e3)" '/usr/bin/python3 -c "import sys; sys.exit(0 if float(\"$e1\") > float(\"$e3\") else 1)"'
bash "$src/pipelines/sweep.sh" "$scene" --ref "$tmp/ref.exr" --tool lt-mutate --option --lambda --values 10,100 \
  --out "$tmp/sl" -- --strategies bidirectional,manifold --mutations 20000 --chains 4 > "$tmp/sllog" 2>&1; code=$?
check "sweep.sh --tool lt-mutate: a row per value and each run's strategy table" \
  '[ $code -eq 0 ] && grep -q "lambda=10.lts" "$tmp/sl/sweep.txt" && [ "$(grep -c "^ *manifold" "$tmp/sl/sweep.txt")" -ge 2 ]'
out=$(bash "$src/pipelines/sweep.sh" "$scene" --ref "$tmp/ref.exr" --tool lt-image --option --x --values 1 2>&1); code=$?
check "sweep.sh: an unknown --tool refused by name" '[ $code -ne 0 ] && echo "$out" | grep -q lt-image'
exit $fail
