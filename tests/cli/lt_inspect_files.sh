#!/usr/bin/env bash
# lt-inspect on lt files: the summary of a buffer file and a paths file, --json (valid, with counts
# that agree with the file), --paths vertex tables, --obj polylines, --histogram bars, stdin, and one
# error line with a non-zero exit for a truncated file or an option that does not fit the file.
#   lt_inspect_files.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$bin/lt-seed" "$src/tests/cli/tiny_box.xml" --spp 2 --seed 1 -o "$tmp/a.lts" --paths "$tmp/a.ltp" --max-paths 50 -q
check "a render with paths to inspect" '[ -s "$tmp/a.lts" ] && [ -s "$tmp/a.ltp" ]'

"$bin/lt-inspect" "$tmp/a.lts" > "$tmp/lts.txt" 2>&1; code=$?
check "buffer file: exit 0" '[ $code -eq 0 ]'
check "buffer file: kind and version" 'grep -q "^kind  *buffer file, format version 1$" "$tmp/lts.txt"'
check "buffer file: producer, command, parameters, scene hash" 'grep -q "^producer  *lt-seed" "$tmp/lts.txt" && grep -q "^command  *.*lt-seed" "$tmp/lts.txt" &&
  grep -q "^parameters .*spp=2" "$tmp/lts.txt" && grep -Eq "^scene .*tiny_box.xml  \(hash [0-9a-f]{16}\)$" "$tmp/lts.txt"'
check "buffer file: chunks" 'grep -q "^chunks  *INFO 1, BUFR 1, STAT 1, END! 1$" "$tmp/lts.txt"'
check "buffer file: size, weight, sample counts" 'grep -q "^buffer  *16 x 16, 3 channels, weighted-mean, weight 512, samples per pixel min 2, mean 2, max 2$" "$tmp/lts.txt"'
check "buffer file: per-channel table" 'grep -Eq "^ +R +[0-9.e-]+ +[0-9.e-]+ +[0-9.e-]+$" "$tmp/lts.txt"'
check "buffer file: STAT table aligned" 'grep -Eq "^ +spp +2$" "$tmp/lts.txt" && grep -Eq "^ +samples +512$" "$tmp/lts.txt"'

"$bin/lt-inspect" "$tmp/a.ltp" > "$tmp/ltp.txt" 2>&1; code=$?
check "paths file: exit 0" '[ $code -eq 0 ]'
check "paths file: kind, count and weights" 'grep -q "^kind  *paths file" "$tmp/ltp.txt" && grep -q "^paths  *50, weight min .*, mean .*, max " "$tmp/ltp.txt"'
check "paths file: length and technique histograms" 'grep -q "^lengths  *.*(edges: paths)$" "$tmp/ltp.txt" && grep -q "^techniques (.*((s,t): paths)$" "$tmp/ltp.txt"'
check "stdin is read like a file" '"$bin/lt-inspect" - < "$tmp/a.ltp" | grep -q "^paths  *50,"'

check "--json is valid and agrees with the file" '"$bin/lt-inspect" "$tmp/a.ltp" --json | python3 -c "
import json, sys
d = json.load(sys.stdin)
assert d[\"kind\"] == \"paths\" and d[\"format_version\"] == 1 and d[\"info\"][\"producer\"] == \"lt-seed\"
assert d[\"chunks\"] == {\"INFO\": 1, \"PATH\": 1, \"STAT\": 1, \"END!\": 1}, d[\"chunks\"]
p = d[\"paths\"]
assert p[\"count\"] == 50 and sum(p[\"length_histogram\"].values()) == 50 and sum(p[\"technique_histogram\"].values()) == 50
assert p[\"weight\"][\"min\"] <= p[\"weight\"][\"mean\"] <= p[\"weight\"][\"max\"]
assert [t[\"name\"] for t in d[\"stats\"]] == [\"normalization\"]
assert \"records\" not in p
"'
check "--json of a buffer file" '"$bin/lt-inspect" "$tmp/a.lts" --json | python3 -c "
import json, sys
b = json.load(sys.stdin)[\"buffers\"][0]
assert (b[\"width\"], b[\"height\"], b[\"channels\"], b[\"weight\"]) == (16, 16, [\"R\", \"G\", \"B\"], 512)
assert b[\"sample_counts\"] == {\"min\": 2, \"mean\": 2, \"max\": 2}
"'
check "--json --paths --limit 2 holds two path records" '"$bin/lt-inspect" "$tmp/a.ltp" --json --paths --limit 2 | python3 -c "
import json, sys
r = json.load(sys.stdin)[\"paths\"][\"records\"]
assert len(r) == 2 and all(len(p[\"vertices\"]) == p[\"s\"] + p[\"t\"] for p in r)
"'

"$bin/lt-inspect" "$tmp/a.ltp" --paths --limit 2 > "$tmp/table.txt" 2>&1; code=$?
check "--paths --limit 2: exit 0" '[ $code -eq 0 ]'
check "--paths --limit 2: two paths with s, t, contribution, weights" '[ "$(grep -c "^path [01]: raster (.*), s=[0-9]* t=[0-9]*, contribution (.*), MIS weight .*, weight " "$tmp/table.txt")" -eq 2 ] && ! grep -q "^path 2:" "$tmp/table.txt"'
check "--paths --limit 2: vertex table header and rows" '[ "$(grep -c "#  *kind  *position  *ng  *ns  *shape/prim  *bsdf  *light  *lobe  *rough  *pdfFwd  *pdfRev" "$tmp/table.txt")" -eq 2 ] &&
  grep -Eq "^ +[0-9]+ +camera " "$tmp/table.txt" && grep -Eq "^ +0 +(light|surface) " "$tmp/table.txt"'

"$bin/lt-inspect" "$tmp/a.ltp" --obj "$tmp/p.obj" >/dev/null 2>&1; code=$?
check "--obj: exit 0" '[ $code -eq 0 ]'
check "--obj: one object and one l element per path" '[ "$(grep -c "^o path_[0-9]*_s[0-9]*_t[0-9]*$" "$tmp/p.obj")" -eq 50 ] && [ "$(grep -c "^l [0-9]" "$tmp/p.obj")" -eq 50 ]'
check "--obj: l elements name existing vertices" 'python3 -c "
import sys
v = 0; ok = True
for line in open(sys.argv[1]):
    w = line.split()
    if w and w[0] == \"v\": v += 1
    if w and w[0] == \"l\": ok &= all(1 <= int(i) <= v for i in w[1:]) and len(w) >= 3
assert ok and v > 0
" "$tmp/p.obj"'
check "--obj --limit 3: three paths" '"$bin/lt-inspect" "$tmp/a.ltp" --obj "$tmp/p3.obj" --limit 3 >/dev/null && [ "$(grep -c "^l " "$tmp/p3.obj")" -eq 3 ]'

"$bin/lt-inspect" "$tmp/a.ltp" --histogram > "$tmp/hist.txt" 2>&1
check "--histogram: two histograms as bars" 'grep -q "^path length (edges)$" "$tmp/hist.txt" && grep -q "^technique (s,t)$" "$tmp/hist.txt" && grep -Eq "^ +\([0-9]+,[0-9]+\)  #+ +[0-9]+$" "$tmp/hist.txt"'

# Cut 20 bytes into chunk 2 (PATH, after INFO): where that is depends on the INFO chunk, which holds
# the command line and so the length of this checkout's paths.
cut=$(/usr/bin/python3 - "$tmp/a.ltp" <<'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
info_length, = struct.unpack_from('<Q', data, 16)  # header 12 bytes, then INFO: tag, length
print(12 + 12 + info_length + 4 + 20)
PY
)
head -c "$cut" "$tmp/a.ltp" > "$tmp/cut.ltp"
out=$("$bin/lt-inspect" "$tmp/cut.ltp" 2>&1); code=$?
check "truncated file: non-zero exit" '[ $code -ne 0 ]'
check "truncated file: one line naming the file" '[ "$(echo "$out" | wc -l)" -eq 1 ] && [[ "$out" == "lt-inspect: error: $tmp/cut.ltp: truncated in chunk 2 (PATH)"* ]]'
out=$("$bin/lt-inspect" "$tmp/a.lts" --paths 2>&1); code=$?
check "--paths on a buffer file: one error line" '[ $code -ne 0 ] && [ "$out" = "lt-inspect: error: $tmp/a.lts: --paths, --obj and --histogram need a paths file, this is a buffer file" ]'
out=$("$bin/lt-inspect" "$src/tests/cli/tiny_box.xml" --obj "$tmp/x.obj" 2>&1); code=$?
check "--obj on a scene: one error line, no file" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && [ ! -e "$tmp/x.obj" ]'
check "scenes are still described" '"$bin/lt-inspect" "$src/tests/cli/tiny_box.xml" | grep -q "^needs"'

exit $fail
