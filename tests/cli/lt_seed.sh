#!/usr/bin/env bash
# lt-seed from the command line: output files are complete and valid, bit-identical data whatever the
# thread count, Ctrl-C keeps the work done, stdout streaming, and bad input gives one error line.
#   lt_seed.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

cat > "$tmp/box.xml" <<'XML'
<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="4"/></integrator>
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="toWorld"><lookat origin="0,0,0.5" target="0,0,-1" up="0,1,0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="2"/></sampler>
    <film type="hdrfilm"><integer name="width" value="20"/><integer name="height" value="16"/><rfilter type="tent"/></film>
  </sensor>
  <shape type="cube"><boolean name="flipNormals" value="true"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0" y="0.6" z="-0.5"/><float name="radius" value="0.2"/>
    <emitter type="area"><rgb name="radiance" value="5"/></emitter></shape>
</scene>
XML

"$bin/lt-seed" "$tmp/box.xml" -o "$tmp/a.lts" --paths "$tmp/a.ltp" --max-paths 50 --threads 1 --seed 3 -q; code=$?
check "renders: exit 0" '[ $code -eq 0 ]'
check "buffer file ends with END!" '[ "$(tail -c 16 "$tmp/a.lts" | head -c 4)" = "END!" ]'
check "paths file ends with END!" '[ "$(tail -c 16 "$tmp/a.ltp" | head -c 4)" = "END!" ]'
"$bin/lt-seed" "$tmp/box.xml" -o "$tmp/b.lts" --paths "$tmp/b.ltp" --max-paths 50 --threads 2 --seed 3 -q
check "same seed, 1 vs 2 threads: identical buffer chunks" '[ "$(chunks "$tmp/a.lts")" = "$(chunks "$tmp/b.lts")" ]'
check "same seed, 1 vs 2 threads: identical path chunks" '[ "$(chunks "$tmp/a.ltp")" = "$(chunks "$tmp/b.ltp")" ]'
"$bin/lt-seed" "$tmp/box.xml" -o "$tmp/c.lts" --threads 2 --seed 4 -q
check "another seed gives another image" '[ "$(chunks "$tmp/a.lts" | grep BUFR)" != "$(chunks "$tmp/c.lts" | grep BUFR)" ]'

# A time limit: an image may end within a pass (pixels normalise by their own counts), a run collecting seeds
# only at a pass's end (their normalization b assumes as many samples in every pixel). At 192 x 192 a pass is
# 36 tiles, so a limit that ignored the rule would almost always cut one short.
"$bin/lt-seed" "$tmp/box.xml" --resolution 192x192 --spp 100000 --time 0.5 -o "$tmp/timed.lts" --paths "$tmp/timed.ltp" -q
check "--time with --paths ends at a pass's end: every pixel has the same sample count" \
  '"$bin/lt-inspect" "$tmp/timed.lts" --json | python3 -c "
import json, sys
c = json.load(sys.stdin)[\"buffers\"][0][\"sample_counts\"]
assert c[\"min\"] == c[\"max\"] and c[\"min\"] >= 1, c
"'

"$bin/lt-seed" "$tmp/box.xml" --spp 1 -o - -q | head -c 4 > "$tmp/head"
check "streams to stdout" '[ "$(cat "$tmp/head")" = "$(printf "LTF\001")" ]'

"$bin/lt-seed" "$tmp/box.xml" --spp 100000 -o "$tmp/int.lts" -q & pid=$!
sleep 2; kill -INT $pid; wait $pid; code=$?
check "Ctrl-C: exit code 130" '[ $code -eq 130 ]'
check "Ctrl-C: a complete file with the work done" '[ "$(tail -c 16 "$tmp/int.lts" | head -c 4)" = "END!" ] && chunks "$tmp/int.lts" | grep -q "^BUFR"'
check "Ctrl-C: no temporary file left" '! ls "$tmp" | grep -q partial'
"$bin/lt-seed" "$tmp/box.xml" --spp 100000 -o "$tmp/term.lts" -q & pid=$!
sleep 2; kill -TERM $pid; wait $pid; code=$?
check "SIGTERM: exit code 143, a complete file" '[ $code -eq 143 ] && [ "$(tail -c 16 "$tmp/term.lts" | head -c 4)" = "END!" ]'

"$bin/lt-seed" "$tmp/box.xml" --spp 100000 -o "$tmp/killed.lts" -q & pid=$!
sleep 2; kill -KILL $pid; wait $pid
check "SIGKILL: nothing under the final name, the temporary file named by its process" \
  '[ ! -e "$tmp/killed.lts" ] && [ -e "$tmp/killed.lts.partial-$pid" ]'
touch "$tmp/killed.lts.partial-$$" "$tmp/killed.lts.partial-12ab"
"$bin/lt-seed" "$tmp/box.xml" --spp 1 -o "$tmp/killed.lts" -q
check "the next run removes a killed run's temporary file, not a running process's nor another name" \
  '[ -e "$tmp/killed.lts" ] && [ ! -e "$tmp/killed.lts.partial-$pid" ] && [ -e "$tmp/killed.lts.partial-$$" ] &&
   [ -e "$tmp/killed.lts.partial-12ab" ]'
rm -f "$tmp/killed.lts.partial-$$" "$tmp/killed.lts.partial-12ab"

out=$("$bin/lt-seed" "$tmp/box.xml" --resolution 200000x200000 -o "$tmp/huge.lts" 2>&1); code=$?
check "a film larger than memory: refused before allocating, one line, no output" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "200000x200000.*GiB of memory" && [ ! -e "$tmp/huge.lts" ]'

out=$(LT_MEMORY_LIMIT=2M "$bin/lt-seed" "$tmp/box.xml" --resolution 1024x1024 -o "$tmp/limited.lts" 2>&1); code=$?
check "LT_MEMORY_LIMIT: a film over the user's limit refused in one line naming both sizes, no output" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "1024x1024.* MiB of memory, more than the 2 MiB available" && [ ! -e "$tmp/limited.lts" ]'
out=$(LT_MEMORY_LIMIT=lots "$bin/lt-seed" "$tmp/box.xml" --spp 1 -o "$tmp/limited.lts" 2>&1); code=$?
check "LT_MEMORY_LIMIT: a malformed value is one error line" \
  '[ $code -ne 0 ] && [ "$out" = "lt-seed: error: LT_MEMORY_LIMIT: '"'lots'"' is not a memory size such as 4G, 512M or 1000000" ] && [ ! -e "$tmp/limited.lts" ]'

out=$("$bin/lt-seed" "$tmp/nope.xml" -o "$tmp/x.lts" 2>&1); code=$?
check "missing scene: non-zero exit, one line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "nope.xml"'
out=$("$bin/lt-seed" "$tmp/box.xml" -o "$tmp/no/such/dir/x.lts" 2>&1); code=$?
check "unwritable output: non-zero exit, names the file" '[ $code -ne 0 ] && echo "$out" | grep -q "no/such/dir"'
out=$("$bin/lt-seed" "$tmp/box.xml" -o "$tmp/x.lts" --resolution 12by5 2>&1); code=$?
check "bad --resolution: non-zero exit, one line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ]'
out=$("$bin/lt-seed" "$tmp/box.xml" -o "$tmp/x.lts" --spp -3 2>&1); code=$?
check "negative --spp refused, saying why in words (not CLI11's range written out in 309 digits)" \
  '[ $code -ne 0 ] && [ "$out" = "lt-seed: error: --spp: must be a positive number, got -3 (--help lists the options)" ]'
out=$("$bin/lt-seed" "$tmp/box.xml" -o "$tmp/x.lts" --threads 100000 2>&1); code=$?
check "--threads beyond any machine refused" \
  '[ $code -ne 0 ] && [ "$out" = "lt-seed: error: --threads: must be a whole number from 0 (all cores) to 1024, got 100000 (--help lists the options)" ]'
out=$("$bin/lt-seed" "$tmp/box.xml" -o "$tmp/x.lts" --threads=-1 2>&1); code=$?
check "--threads -1 refused" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "^lt-seed: error: --threads: must be a whole number"'
check "no output left behind by failed runs" '[ ! -e "$tmp/x.lts" ]'
"$bin/lt-seed" "$tmp/box.xml" -o "$tmp/r.lts" --resolution 8x6 --method pt -q
check "--resolution and --method pt" '[ "$(tail -c 16 "$tmp/r.lts" | head -c 4)" = "END!" ]'
for m in pt bdpt; do
  "$bin/lt-seed" "$tmp/box.xml" -o "$tmp/s-$m.lts" --resolution 8x6 --method $m --sampler sobol --spp 4 -q
  check "--sampler sobol with --method $m: a complete file that records the sampler" \
    '[ "$(tail -c 16 "$tmp/s-$m.lts" | head -c 4)" = "END!" ] && "$bin/lt-inspect" "$tmp/s-$m.lts" | grep -q "sobol"'
done
out=$("$bin/lt-seed" "$tmp/box.xml" -o "$tmp/x.lts" --sampler halton 2>&1); code=$?
check "an unknown --sampler refused in one line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && [ ! -e "$tmp/x.lts" ]'
exit $fail
