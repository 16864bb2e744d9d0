#!/usr/bin/env bash
# lt-error from the command line: renders at 1 and 8 spp measured against a 64-spp EXR reference; the
# table, the CSV, the JSON, the plot and the error map; one error line and a non-zero exit for a
# reference of another size.
#   lt_error.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
scene="$src/tests/cli/tiny_box.xml"
"$bin/lt-seed" "$scene" --spp 1 --seed 1 -o spp1.lts -q
"$bin/lt-seed" "$scene" --spp 8 --seed 2 -o spp8.lts -q
"$bin/lt-seed" "$scene" --spp 64 --seed 3 -o ref.lts -q
"$bin/lt-image" ref.lts -o ref.exr 2>/dev/null
check "renders and reference" '[ -s spp1.lts ] && [ -s spp8.lts ] && [ -s ref.exr ]'

out=$("$bin/lt-error" spp1.lts spp8.lts --ref ref.exr 2>&1); code=$?
echo "$out"
check "table: exit 0" '[ $code -eq 0 ]'
check "table: header" '[[ "$(echo "$out" | head -1)" =~ ^input\ +image\ +time\ \[s\]\ +samples\ +relMSE\ +efficiency\ +scale\ +relMSE\ rescaled$ ]]'
# 16 x 16 pixels: 256 samples at 1 spp, 2048 at 8 spp; the time comes from the file's STAT "run" table.
check "table: a row per input with its samples" 'echo "$out" | grep -Eq "^spp1.lts +BUFR +[0-9.]+ +256 " &&
  echo "$out" | grep -Eq "^spp8.lts +BUFR +[0-9.]+ +2048 " && [ "$(echo "$out" | wc -l)" -eq 3 ]'
e1=$(echo "$out" | awk '$1 == "spp1.lts" { print $5 }')
e8=$(echo "$out" | awk '$1 == "spp8.lts" { print $5 }')
# relMSE is the variance of an unbiased estimate over its squared mean, so it falls as 1/spp: 8 spp
# should have about 1/8 of the 1-spp error (plus the 64-spp reference's own variance, 1/64 of the 1-spp
# error, in both). Each value averages 256 pixels, so it fluctuates by tens of percent at most; asking
# only for a factor 2 leaves a margin of 4 over the expected factor 8.
check "8 spp has less than half the error of 1 spp ($e8 vs $e1)" 'awk -v a="$e1" -v b="$e8" "BEGIN { exit !(b > 0 && b < a / 2) }"'

# A run with snapshots: one row per snapshot (samples so far), then the final buffer, times increasing.
"$bin/lt-seed" "$scene" --spp 8 --snapshot-samples 1,2,4 --seed 4 -o snaps.lts -q
"$bin/lt-error" snaps.lts --ref ref.exr --csv snaps.csv > /dev/null 2>&1; code=$?
check "snapshots: a row each, then BUFR" '[ $code -eq 0 ] &&
  [ "$(tail -n +2 snaps.csv | cut -d, -f2,5 | tr "\n" "|")" = "SNAP 1 of 3,256|SNAP 2 of 3,512|SNAP 3 of 3,1024|BUFR,2048|" ]'
check "snapshots: times increase" 'tail -n +2 snaps.csv | cut -d, -f3 | awk "NR > 1 && \$1 < t { exit 1 } { t = \$1 }"'

out=$("$bin/lt-error" spp1.lts spp8.lts --ref ref.exr --trim 0.01 2>&1); code=$?
check "--trim says how many pixels it dropped" '[ $code -eq 0 ] && echo "$out" | grep -q "^trimmed 2 of 256 pixels per image"'

"$bin/lt-error" spp1.lts spp8.lts ref.exr --ref ref.exr --csv rows.csv > /dev/null 2>&1; code=$?
check "--csv: exit 0" '[ $code -eq 0 ]'
check "--csv: header" '[ "$(head -1 rows.csv)" = "input,label,time,cpu_time,samples,metric,error,efficiency,scale,error_rescaled" ]'
check "--csv: one row per input" '[ "$(wc -l < rows.csv)" -eq 4 ] &&
  grep -Eq "^spp1.lts,BUFR,[0-9.e-]+,[0-9.e-]+,256,relMSE,[0-9.e-]+,[0-9.e+-]+,[0-9.e+-]+,[0-9.e+-]+$" rows.csv &&
  grep -Eq "^spp8.lts,BUFR,[0-9.e-]+,[0-9.e-]+,2048,relMSE,[0-9.e-]+,[0-9.e+-]+,[0-9.e+-]+,[0-9.e+-]+$" rows.csv'
# The reference against itself: error 0, no time (an EXR carries none), so no efficiency; scale 1.
check "--csv: EXR row without a time" 'grep -q "^ref.exr,EXR,,,,relMSE,0,,1,0$" rows.csv'

check "--json is valid JSON with the rows" '"$bin/lt-error" spp1.lts spp8.lts --ref ref.exr --metric rrmse --json 2>/dev/null |
  python3 -c "import json, sys; j = json.load(sys.stdin); assert j[\"metric\"] == \"rRMSE\", j; assert [r[\"samples\"] for r in j[\"rows\"]] == [256, 2048], j"'

out=$("$bin/lt-error" spp1.lts spp8.lts --ref ref.exr --plot curve.png --map map.exr 2>&1); code=$?
check "--plot --map: exit 0" '[ $code -eq 0 ] || { echo "$out"; false; }'
check "--plot writes a PNG" '[ "$(magic curve.png 8)" = "89504e470d0a1a0a" ]'
check "--map writes an EXR with channel error" '[ "$(magic map.exr 4)" = "762f3101" ] &&
  "$bin/lt-inspect" map.exr --json | python3 -c "import json, sys; b = json.load(sys.stdin)[\"buffers\"][0]; assert b[\"channels\"] == [\"error\"], b"'
check "no temporary files left" '[ -z "$(ls | grep partial)" ]'

"$bin/lt-seed" "$scene" --spp 1 --resolution 8x8 -o small.lts -q
"$bin/lt-image" small.lts -o small.exr 2>/dev/null
out=$("$bin/lt-error" spp1.lts --ref small.exr --csv bad.csv 2>&1); code=$?
check "mismatched resolution: one error line, non-zero exit" '[ $code -ne 0 ] &&
  [ "$out" = "lt-error: error: cannot compare spp1.lts with small.exr: sizes differ (16x16 and 8x8)" ] && [ ! -e bad.csv ]'
out=$("$bin/lt-error" spp1.lts --ref ref.exr --crop 12,12,8,8 2>&1); code=$?
check "crop outside the image: one error line" '[ $code -ne 0 ] && [ "$out" = "lt-error: error: crop 12,12,8,8 does not fit the 16x16 image" ]'
check "--help exits 0" '"$bin/lt-error" --help | grep -q "lt-error"'

exit $fail
