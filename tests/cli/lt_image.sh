#!/usr/bin/env bash
# lt-image from the command line: a tiny render developed into a valid EXR and PNG, two seeds merged by
# weight (the merged image's channel means are the weighted means of the inputs'), EXR input, and one
# error line with a non-zero exit for each kind of bad input.
#   lt_image.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scene="$src/tests/cli/tiny_box.xml"
"$bin/lt-seed" "$scene" --spp 2 --seed 1 -o "$tmp/a.lts" -q
"$bin/lt-seed" "$scene" --spp 4 --seed 2 -o "$tmp/b.lts" -q
check "two renders to develop" '[ -s "$tmp/a.lts" ] && [ -s "$tmp/b.lts" ]'

out=$("$bin/lt-image" "$tmp/a.lts" -o "$tmp/a.exr" --png "$tmp/a.png" 2>&1); code=$?
check "develop: exit 0" '[ $code -eq 0 ]'
check "develop: one line saying what it wrote" '[ "$(echo "$out" | wc -l)" -eq 1 ] && [[ "$out" == "lt-image: wrote $tmp/a.exr and $tmp/a.png: 16x16, 3 channels, weight 512" ]]'
check "EXR magic 76 2f 31 01" '[ "$(magic "$tmp/a.exr" 4)" = "762f3101" ]'
check "PNG signature" '[ "$(magic "$tmp/a.png" 8)" = "89504e470d0a1a0a" ]'
check "PNG is 16 x 16 RGB" 'file "$tmp/a.png" | grep -q "16 x 16, 8-bit/color RGB"'
check "no temporary files left" '[ -z "$(ls "$tmp" | grep partial)" ]'
check "INFO carried into the EXR" 'grep -aq "lt:info" "$tmp/a.exr" && grep -aq "lt-seed" "$tmp/a.exr"'
check "--png alone" '"$bin/lt-image" "$tmp/a.lts" --png "$tmp/only.png" 2>/dev/null && cmp -s "$tmp/only.png" "$tmp/a.png"'
# The EXR header holds its creation date, so compare what lt-inspect reads from it.
check "stdin input" '"$bin/lt-image" - -o "$tmp/stdin.exr" < "$tmp/a.lts" 2>/dev/null &&
  [ "$("$bin/lt-inspect" "$tmp/stdin.exr" --json | grep -v '"file"')" = "$("$bin/lt-inspect" "$tmp/a.exr" --json | grep -v '"file"')" ]'

out=$("$bin/lt-image" "$tmp/a.lts" "$tmp/b.lts" -o "$tmp/m.exr" 2>&1); code=$?
check "merge: exit 0" '[ $code -eq 0 ]'
check "merge: says how many files and the total weight" '[[ "$out" == *"merged 2 files (weighted-mean), weight 1536"* ]]'
# Per-channel means are linear, so the merged image's means are the weighted means of the inputs'.
"$bin/lt-inspect" "$tmp/a.lts" --json > "$tmp/a.json"
"$bin/lt-inspect" "$tmp/b.lts" --json > "$tmp/b.json"
"$bin/lt-inspect" "$tmp/m.exr" --json > "$tmp/m.json"
check "merge: channel means are the weighted means" 'python3 - "$tmp" <<PY
import json, sys
d = sys.argv[1]
a, b, m = (json.load(open(f"{d}/{n}.json"))["buffers"][0] for n in "abm")
assert (a["weight"], b["weight"]) == (512, 1024)
for c in "RGB":
    want = (a["weight"] * a["channel_stats"][c]["mean"] + b["weight"] * b["channel_stats"][c]["mean"]) / 1536
    got = m["channel_stats"][c]["mean"]
    assert abs(got - want) <= 1e-6 * abs(want), (c, got, want)
    # and it is not simply one of the inputs
    assert got != a["channel_stats"][c]["mean"] and got != b["channel_stats"][c]["mean"]
PY'
check "EXR input merges with weight 1" '"$bin/lt-image" "$tmp/a.exr" "$tmp/m.exr" -o "$tmp/e.exr" 2>&1 | grep -q "merged 2 files (weighted-mean), weight 2"'

out=$("$bin/lt-image" -o "$tmp/x.exr" 2>&1); code=$?
check "no input: non-zero exit" '[ $code -ne 0 ] && [[ "$out" == *"IN is required"* ]]'
out=$("$bin/lt-image" "$tmp/a.lts" 2>&1); code=$?
check "no output: one error line" '[ $code -ne 0 ] && [ "$out" = "lt-image: error: nothing to write: give -o OUT.exr and/or --png OUT.png" ]'
out=$("$bin/lt-image" "$tmp/missing.lts" -o "$tmp/x.exr" 2>&1); code=$?
check "missing input: one line naming it" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && [[ "$out" == "lt-image: error: $tmp/missing.lts: "* ]]'
head -c 300 "$tmp/a.lts" > "$tmp/cut.lts"
out=$("$bin/lt-image" "$tmp/cut.lts" -o "$tmp/x.exr" 2>&1); code=$?
check "truncated input: the reader's one line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && [[ "$out" == "lt-image: error: $tmp/cut.lts: truncated"* ]]'
check "failed runs leave no output" '[ ! -e "$tmp/x.exr" ] && [ -z "$(ls "$tmp" | grep partial)" ]'
"$bin/lt-seed" "$scene" --spp 1 --resolution 8x8 -o "$tmp/small.lts" -q
out=$("$bin/lt-image" "$tmp/a.lts" "$tmp/small.lts" -o "$tmp/x.exr" 2>&1); code=$?
check "mismatched sizes: one line naming both files" '[ $code -ne 0 ] && [ "$out" = "lt-image: error: cannot merge $tmp/a.lts and $tmp/small.lts: sizes differ (16x16 and 8x8)" ]'
check "--help exits 0" '"$bin/lt-image" --help | grep -q "lt-image"'

exit $fail
