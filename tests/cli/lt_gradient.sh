#!/usr/bin/env bash
# lt-gradient from the command line: both methods write the planes lt-reconstruct reads (and their variance
# planes), bit-identical data whatever the thread count, a time limit that ends G-PT at a pass's end,
# snapshots that lt-reconstruct reconstructs and lt-error measures, Ctrl-C keeps the work done, and nonsense
# options give one error line and no file.
#   lt_gradient.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scene="$src/tests/cli/tiny_box.xml"

for m in gpt gdpr; do
  "$bin/lt-gradient" "$scene" --method $m --spp 4 --threads 1 --seed 3 -o "$tmp/$m-1.lts" -q; code=$?
  check "$m: exit 0, a complete file" '[ $code -eq 0 ] && [ "$(tail -c 16 "$tmp/$m-1.lts" | head -c 4)" = "END!" ]'
  "$bin/lt-gradient" "$scene" --method $m --spp 4 --threads 2 --seed 3 -o "$tmp/$m-2.lts" -q
  check "$m: same seed, 1 vs 2 threads: identical buffer" \
    '[ "$(chunks "$tmp/$m-1.lts" | grep BUFR)" = "$(chunks "$tmp/$m-2.lts" | grep BUFR)" ]'
  check "$m: the planes lt-reconstruct reads, and the shift statistics" '"$bin/lt-inspect" "$tmp/$m-1.lts" --json |
    python3 -c "
import json, sys
d = json.load(sys.stdin)
b = d[\"buffers\"][0]
names = b[\"channels\"]
assert names[:3] == [\"primal.R\", \"primal.G\", \"primal.B\"] and \"dx.R\" in names and \"direct.B\" in names, names
assert all(p + \".var\" in names for p in (\"primal\", \"dx\", \"dy\", \"direct\")), names
assert b[\"channel_stats\"][\"primal.var\"][\"max\"] > 0, b[\"channel_stats\"][\"primal.var\"]
t = [s for s in d[\"stats\"] if s[\"name\"] == \"shift\"][0]
assert t[\"rows\"][1] == \"shifts\"
"'
  "$bin/lt-reconstruct" "$tmp/$m-1.lts" -o "$tmp/$m.exr" -q; code=$?
  check "$m: lt-reconstruct reads it" '[ $code -eq 0 ] && [ "$(magic "$tmp/$m.exr" 4)" = "762f3101" ]'
done

"$bin/lt-gradient" "$scene" --method gdpr --time 2 --snapshots 0.2,0.5 -o - -q | "$bin/lt-reconstruct" - -o "$tmp/snap.lts" -q
check "snapshots: reconstructed, each with its time" '[ "$(chunks "$tmp/snap.lts" | grep -c SNAP)" -eq 2 ]'
"$bin/lt-seed" "$scene" --method pt --spp 64 -o "$tmp/ref.lts" -q
check "lt-error measures the reconstructed snapshots" \
  '[ "$("$bin/lt-error" "$tmp/snap.lts" --ref "$tmp/ref.lts" | grep -c SNAP)" -eq 2 ]'

# A time limit: G-PT's samples credit their neighbours, so it ends only at a pass's end (every pixel has the
# same number of base paths); path reusing may end after any tile.
# At 192 x 192 a pass is 36 tiles, so a limit that ignored the rule would almost always cut one short.
"$bin/lt-gradient" "$scene" --method gpt --resolution 192x192 --time 0.5 -o "$tmp/timed.lts" -q
check "gpt --time ends at a pass's end: every pixel has the same sample count" '"$bin/lt-inspect" "$tmp/timed.lts" --json |
    python3 -c "
import json, sys
c = json.load(sys.stdin)[\"buffers\"][0][\"sample_counts\"]
assert c[\"min\"] == c[\"max\"] and c[\"min\"] >= 1, c
"'

"$bin/lt-gradient" "$scene" --spp 100000 -o "$tmp/int.lts" -q & pid=$!
sleep 2; kill -INT $pid; wait $pid; code=$?
check "Ctrl-C: exit code 130, a complete file" '[ $code -eq 130 ] && [ "$(tail -c 16 "$tmp/int.lts" | head -c 4)" = "END!" ]'
"$bin/lt-gradient" "$scene" --spp 100000 -o "$tmp/term.lts" -q & pid=$!
sleep 2; kill -TERM $pid; wait $pid; code=$?
check "SIGTERM: exit code 143, a complete file" '[ $code -eq 143 ] && [ "$(tail -c 16 "$tmp/term.lts" | head -c 4)" = "END!" ]'

# Gradient-domain MLT: lt-mutate's chain-state stream through the gradient stage into lt-reconstruct, in one
# pipeline; a cut or damaged stream, another scene's stream and the path tracers' options are refused.
"$bin/lt-mutate" "$scene" --mutations-per-pixel 16 --seed 2 -o "$tmp/mlt.lts" --stream - -q |
  "$bin/lt-gradient" "$scene" --from-paths - --snapshots 0.001 -o - -q | "$bin/lt-reconstruct" - -o "$tmp/gdmlt.lts" -q
codes="${PIPESTATUS[*]}"
check "gdmlt: lt-mutate --stream | lt-gradient --from-paths | lt-reconstruct" \
  '[ "$codes" = "0 0 0" ] && [ "$(chunks "$tmp/gdmlt.lts" | grep -c "BUFR\|SNAP")" -ge 2 ]'
"$bin/lt-seed" "$scene" --spp 2 -o "$tmp/seed.lts" --paths - -q |
  "$bin/lt-mutate" "$scene" - --target gradient --mutations-per-pixel 8 --startup-samples 2000 -o "$tmp/gd.lts" \
    --stream - -q | "$bin/lt-gradient" "$scene" --from-paths - -o - -q | "$bin/lt-reconstruct" - -o "$tmp/gd-r.lts" -q
codes="${PIPESTATUS[*]}"
check "gdmlt: lt-seed | lt-mutate --target gradient | lt-gradient --from-paths | lt-reconstruct" \
  '[ "$codes" = "0 0 0 0" ] && "$bin/lt-inspect" "$tmp/gd.lts" | grep -q "target=gradient"'
out=$("$bin/lt-mutate" "$scene" --space primary --target gradient --mutations 100 -o "$tmp/x.lts" 2>&1); code=$?
check "--target gradient outside path space: refused" '[ $code -ne 0 ] && echo "$out" | grep -q "needs --space path"'
out=$("$bin/lt-mutate" "$scene" --gradient-alpha 0.5 --mutations 100 -o "$tmp/x.lts" 2>&1); code=$?
check "--gradient-alpha without --target gradient: refused" '[ $code -ne 0 ] && echo "$out" | grep -q "target gradient"'
sed 's|<sensor type="perspective">|<sensor type="thinlens"><float name="apertureRadius" value="0.1"/>|' "$scene" \
  > "$tmp/lens.xml"
out=$("$bin/lt-mutate" "$tmp/lens.xml" --mutations 1000 -o "$tmp/x.lts" --stream "$tmp/x.ltp" 2>&1); code=$?
check "--stream with a thin lens: refused (no lens points in the stream), no file" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "lens.xml.*thinlens" &&
   [ ! -e "$tmp/x.lts" ] && [ ! -e "$tmp/x.ltp" ]'
"$bin/lt-mutate" "$scene" --mutations-per-pixel 16 --seed 2 -o "$tmp/mlt.lts" --stream "$tmp/stream.ltp" -q
out=$("$bin/lt-gradient" "$tmp/lens.xml" --from-paths "$tmp/stream.ltp" -o "$tmp/x.lts" 2>&1); code=$?
check "--from-paths with a thin lens: refused, no file" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "thinlens" && [ ! -e "$tmp/x.lts" ]'
check "the stream: chain-state chunks that lt-inspect lists" '"$bin/lt-inspect" "$tmp/stream.ltp" | grep -q CHST'
head -c $(( $(stat -c %s "$tmp/stream.ltp") * 2 / 3 )) "$tmp/stream.ltp" > "$tmp/cut.ltp"
out=$("$bin/lt-gradient" "$scene" --from-paths "$tmp/cut.ltp" -o "$tmp/x.lts" 2>&1); code=$?
check "a cut stream: one error line naming it" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "cut.ltp.*truncated"'
python3 -c "
import sys; b = bytearray(open(sys.argv[1], 'rb').read()); b[len(b) // 2] ^= 0x40; open(sys.argv[2], 'wb').write(b)
" "$tmp/stream.ltp" "$tmp/bad.ltp"
out=$("$bin/lt-gradient" "$scene" --from-paths "$tmp/bad.ltp" -o "$tmp/x.lts" 2>&1); code=$?
check "a damaged stream: one error line naming it" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "bad.ltp"'
out=$("$bin/lt-gradient" "$src/scenes/cornell-box/scene.xml" --from-paths "$tmp/stream.ltp" -o "$tmp/x.lts" 2>&1)
code=$?
check "another scene's stream: refused" '[ $code -ne 0 ] && echo "$out" | grep -q "made for scene"'
out=$("$bin/lt-gradient" "$scene" --from-paths "$tmp/stream.ltp" --spp 4 -o "$tmp/x.lts" 2>&1); code=$?
check "--spp with --from-paths: refused" '[ $code -ne 0 ] && echo "$out" | grep -q "not an option of --from-paths"'

out=$("$bin/lt-gradient" "$scene" --method gpt --tile 4 -o "$tmp/x.lts" 2>&1); code=$?
check "--tile with gpt: refused in one line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q gdpr'
out=$("$bin/lt-gradient" "$scene" --method bdpt -o "$tmp/x.lts" 2>&1); code=$?
check "unknown method: refused" '[ $code -ne 0 ] && echo "$out" | grep -q method'
"$bin/lt-gradient" "$scene" --rr-min 2 -o "$tmp/x.lts" >/dev/null 2>&1; code=$?
check "--rr-min outside [0, 1]: refused" '[ $code -ne 0 ]'
check "no output left behind by refused runs" '[ ! -e "$tmp/x.lts" ]'
exit $fail
