#!/usr/bin/env bash
# lt-mutate from the command line: complete output with statistics, bit-identical images whatever the
# thread count, seeds from a pipe, snapshots for lt-error, Ctrl-C keeps the work done, one error line
# for bad input.
#   lt_mutate.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scene="$src/tests/cli/tiny_box.xml"

for space in path primary multiplexed; do
    "$bin/lt-mutate" "$scene" --space $space --mutations 20000 --chains 16 --startup-samples 2000 --threads 1 --seed 5 \
        -o "$tmp/$space-1.lts" -q; code=$?
    check "$space: exit 0, complete file" '[ $code -eq 0 ] && [ "$(tail -c 16 "$tmp/$space-1.lts" | head -c 4)" = "END!" ]'
    "$bin/lt-mutate" "$scene" --space $space --mutations 20000 --chains 16 --startup-samples 2000 --threads 2 --seed 5 \
        -o "$tmp/$space-2.lts" -q
    check "$space: 1 vs 2 threads, identical image" \
        '[ "$(chunks "$tmp/$space-1.lts" | grep ^BUFR)" = "$(chunks "$tmp/$space-2.lts" | grep ^BUFR)" ]'
    stats=$("$bin/lt-inspect" "$tmp/$space-1.lts")
    check "$space: strategy statistics stored" 'echo "$stats" | grep -q "stat *strategies"'
    check "$space: normalization stored" 'echo "$stats" | grep -q "startup_samples"'
    # b is refined during the run (large steps; path space: BDPT samples), so it has more samples than the
    # start-up drew, and its standard error is stored.
    check "$space: b refined during the run, its error stored" 'echo "$stats" | grep -q "b_relative_standard_error" &&
      echo "$stats" | awk "/^ +b_samples / { n = \$2 } /^ +startup_samples / { s = \$2 } END { exit !(n > s) }"'
done
stats=$("$bin/lt-inspect" "$tmp/multiplexed-1.lts")
check "multiplexed: per-length table with b, its error, chains and mutations" \
    'echo "$stats" | grep -q "b_standard_error *b_samples *chains_started *mutations"'
out=$("$bin/lt-mutate" "$scene" --space primary --refine-b 0.1 --time 1 -o "$tmp/x.lts" 2>&1); code=$?
check "--refine-b with a primary space: one error line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] &&
  echo "$out" | grep -q "large steps"'

"$bin/lt-seed" "$scene" --spp 1 --paths - -o "$tmp/seed.lts" -q | \
    "$bin/lt-mutate" "$scene" - --mutations 5000 --chains 8 --startup-samples 1000 -o "$tmp/piped.lts" 2> "$tmp/err"; code=$?
check "seeds from a pipe: exit 0" '[ $code -eq 0 ]'
check "seeds from a pipe: says how it used them" 'grep -q "seed paths" "$tmp/err"'
check "the end-of-run table names the strategies" 'grep -q "^bidirectional" "$tmp/err"'
check "--strategies auto says what it left out and why" 'grep -q "left out: lens" "$tmp/err"'

"$bin/lt-mutate" "$scene" --mutations-per-pixel 64 --chains 8 --startup-samples 1000 --snapshot-mutations 8,16,32 \
    -o "$tmp/snap.lts" -q
"$bin/lt-image" "$tmp/snap.lts" -o "$tmp/ref.exr" -q 2>/dev/null || "$bin/lt-image" "$tmp/snap.lts" -o "$tmp/ref.exr" > /dev/null 2>&1
table=$("$bin/lt-error" "$tmp/snap.lts" --ref "$tmp/ref.exr" 2>&1)
check "snapshots: lt-error lists three of them" '[ "$(echo "$table" | grep -c SNAP)" -eq 3 ]'

"$bin/lt-mutate" "$scene" --mutations 1000000000 --chains 8 --startup-samples 1000 -o "$tmp/int.lts" -q & pid=$!
sleep 2; kill -INT $pid; wait $pid; code=$?
check "Ctrl-C: exit code 130" '[ $code -eq 130 ]'
check "Ctrl-C: a complete file with the work done" '[ "$(tail -c 16 "$tmp/int.lts" | head -c 4)" = "END!" ] && chunks "$tmp/int.lts" | grep -q "^BUFR"'
"$bin/lt-mutate" "$scene" --mutations 1000000000 --chains 8 --startup-samples 1000 -o "$tmp/term.lts" -q & pid=$!
sleep 2; kill -TERM $pid; wait $pid; code=$?
check "SIGTERM: exit code 143, a complete file" '[ $code -eq 143 ] && [ "$(tail -c 16 "$tmp/term.lts" | head -c 4)" = "END!" ]'

out=$("$bin/lt-mutate" "$scene" --chains 2000000000 --mutations 10 --startup-samples 1000 -o "$tmp/many.lts" -q 2>&1); code=$?
check "more chains than memory holds: one error line naming them, no output" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "a run of 2000000000 chains needs .* GiB of memory" && [ ! -e "$tmp/many.lts" ]'

out=$("$bin/lt-mutate" "$scene" -o "$tmp/x.lts" 2>&1); code=$?
check "no length given: one error line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ]'
out=$("$bin/lt-mutate" "$scene" --time 1 --strategies bidirectional,portl -o "$tmp/x.lts" 2>&1); code=$?
check "an unknown strategy is refused by name, the available ones listed" \
    '[ $code -ne 0 ] && echo "$out" | grep -q "unknown mutation .portl." && echo "$out" | grep -q "portal"'
out=$("$bin/lt-mutate" "$scene" --time 1 --strategies bidirectional,manifold --lambda 0 -o "$tmp/x.lts" 2>&1); code=$?
check "--lambda 0 refused" '[ $code -ne 0 ] && echo "$out" | grep -q lambda'
out=$("$bin/lt-mutate" "$scene" --time 1 --strategies bidirectional,manifold --lambda nan -o "$tmp/x.lts" 2>&1); code=$?
check "--lambda nan refused before any work, in one line" \
    '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "lambda: must be a positive number, got nan"'
out=$("$bin/lt-mutate" "$scene" --time 1 --space primary --lambda 10 -o "$tmp/x.lts" 2>&1); code=$?
check "--lambda with a primary space refused" '[ $code -ne 0 ] && echo "$out" | grep -q "lambda is for --space path"'
out=$("$bin/lt-mutate" "$src/tests/cli/nope.xml" --time 1 -o "$tmp/x.lts" 2>&1); code=$?
check "missing scene: one line naming it" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q nope.xml'
printf 'LTF\001garbage' > "$tmp/bad.ltp"
out=$("$bin/lt-mutate" "$scene" "$tmp/bad.ltp" --time 1 -o "$tmp/x.lts" 2>&1); code=$?
check "corrupt seed file: one line naming it" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q bad.ltp'
"$bin/lt-seed" "$src/scenes/cornell-spheres/scene.xml" --spp 1 --resolution 8x8 --paths "$tmp/other.ltp" -o "$tmp/o.lts" -q
out=$("$bin/lt-mutate" "$scene" "$tmp/other.ltp" --time 1 -o "$tmp/x.lts" 2>&1); code=$?
check "seeds of another scene: refused" '[ $code -ne 0 ] && echo "$out" | grep -q "scene"'
# The direct split (default): seeds must be made for the same kind of chains, the output says how much came from each part.
"$bin/lt-seed" "$scene" --spp 1 --paths "$tmp/all.ltp" --direct-split off -o "$tmp/o.lts" -q
out=$("$bin/lt-mutate" "$scene" "$tmp/all.ltp" --time 1 -o "$tmp/x.lts" 2>&1); code=$?
check "seeds with the direct part's paths for chains without them: one line naming the file and the fix" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "all.ltp:.*lt-seed --direct-split on"'
"$bin/lt-seed" "$scene" --spp 1 --paths "$tmp/split.ltp" -o "$tmp/o.lts" -q
out=$("$bin/lt-mutate" "$scene" "$tmp/split.ltp" --direct-samples -1 --time 1 -o "$tmp/x.lts" 2>&1); code=$?
check "seeds without the direct part's paths for chains that render every path: refused in one line" \
  '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "split.ltp:.*--direct-split off"'
"$bin/lt-mutate" "$scene" "$tmp/split.ltp" --mutations 5000 --chains 8 -o "$tmp/split.lts" -q; code=$?
stats=$("$bin/lt-inspect" "$tmp/split.lts")
check "the direct split: exit 0, direct.R/G/B and the direct_split table in the output" \
  '[ $code -eq 0 ] && echo "$stats" | grep -q "direct.G" && echo "$stats" | grep -q "direct_share"'
out=$("$bin/lt-mutate" "$scene" --direct-samples 0 --time 1 -o "$tmp/x.lts" 2>&1); code=$?
check "--direct-samples 0 refused in one line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q direct-samples'
out=$("$bin/lt-seed" "$scene" --spp 1 --direct-split off -o "$tmp/x.lts" 2>&1); code=$?
check "lt-seed --direct-split without --paths refused" '[ $code -ne 0 ] && echo "$out" | grep -q "needs --paths"'
"$bin/lt-mutate" "$scene" --large-step 2 --time 1 -o "$tmp/x.lts" > /dev/null 2>&1; code=$?
check "large-step probability above 1 refused" '[ $code -ne 0 ]'
check "no output left behind by failed runs" '[ ! -e "$tmp/x.lts" ]'

# Veach's perturbations: an explicit weighted mix runs and the table lists each; auto on a scene without
# specular surfaces leaves out the caustic and multi-chain perturbations and says why.
"$bin/lt-mutate" "$src/scenes/cornell-spheres/scene.xml" --resolution 16x16 \
    --strategies bidirectional,lens:2,caustic,lens-subpath --mutations 20000 --chains 8 --startup-samples 2000 \
    -o "$tmp/mix.lts" 2> "$tmp/mix-err"; code=$?
check "bidirectional,lens:2,caustic,lens-subpath: exit 0" '[ $code -eq 0 ]'
check "bidirectional,lens:2,caustic,lens-subpath: the table lists all four" \
    'grep -q "^bidirectional" "$tmp/mix-err" && grep -q "^lens " "$tmp/mix-err" && grep -q "^caustic" "$tmp/mix-err" &&
     grep -q "^lens-subpath" "$tmp/mix-err"'
# The manifold perturbation: its rejection table has the walk columns, its lambda is in the file's INFO.
"$bin/lt-mutate" "$src/scenes/cornell-spheres/scene.xml" --resolution 16x16 --strategies bidirectional,manifold \
    --lambda 20 --mutations 20000 --chains 8 --startup-samples 2000 -o "$tmp/me.lts" 2> "$tmp/me-err"; code=$?
check "bidirectional,manifold: exit 0, walk columns" \
    '[ $code -eq 0 ] && grep -q "^manifold" "$tmp/me-err" && grep -q "walk failed" "$tmp/me-err"'
check "bidirectional,manifold: lambda and the walk figures stored" '"$bin/lt-inspect" "$tmp/me.lts" | grep -q "lambda" && "$bin/lt-inspect" "$tmp/me.lts" | grep -q "walks.manifold"'
# HSLT: its walk figures (Table 3 of the paper) printed and stored, its parameters in INFO.
"$bin/lt-mutate" "$src/scenes/cornell-spheres/scene.xml" --resolution 16x16 --strategies bidirectional,hslt \
    --hslt-gamma 0.2 --hslt-stratify 0.05 --hslt-jumps on --mutations 20000 --chains 8 --startup-samples 2000 -o "$tmp/hs.lts" \
    2> "$tmp/hs-err"; code=$?
check "bidirectional,hslt: exit 0, walk figures with projection orders and acceptance by length" \
    '[ $code -eq 0 ] && grep -q "^hslt" "$tmp/hs-err" && grep -q "projected from the eye / light" "$tmp/hs-err" &&
    grep -q "jumps tried / proposed" "$tmp/hs-err" &&
     grep -q "acceptance by chain length" "$tmp/hs-err"'
check "bidirectional,hslt: gamma, image step and the walk table stored" \
    '"$bin/lt-inspect" "$tmp/hs.lts" | grep -q "hslt_gamma" && "$bin/lt-inspect" "$tmp/hs.lts" | grep -q "hslt_jumps=true" &&
     "$bin/lt-inspect" "$tmp/hs.lts" | grep -q "walks.hslt"'
out=$("$bin/lt-mutate" "$scene" --time 1 --strategies bidirectional,hslt --hslt-gamma 0 -o "$tmp/x.lts" 2>&1); code=$?
check "--hslt-gamma 0 refused in one line" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q gamma'
out=$("$bin/lt-mutate" "$scene" --time 1 --strategies bidirectional,hslt --hslt-stratify nan -o "$tmp/x.lts" 2>&1); code=$?
check "--hslt-stratify nan refused before any work, in one line, no output" \
    '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q "hslt-stratify" && [ ! -e "$tmp/x.lts" ]'
out=$("$bin/lt-mutate" "$scene" --time 1 --space primary --hslt-gamma 0.2 -o "$tmp/x.lts" 2>&1); code=$?
check "--hslt-gamma outside path space refused" '[ $code -ne 0 ] && echo "$out" | grep -q "space path"'
out=$("$bin/lt-mutate" "$scene" --time 1 --strategies bidirectional,hslt --hslt-jumps maybe -o "$tmp/x.lts" 2>&1); code=$?
check "--hslt-jumps takes on or off only (CLI11's message, naming the option), no output" \
    '[ $code -ne 0 ] && echo "$out" | head -1 | grep -q "hslt-jumps" && [ ! -e "$tmp/x.lts" ]'
"$bin/lt-mutate" "$src/scenes/cornell-spheres/scene.xml" --resolution 16x16 --strategies bidirectional,manifold \
    --mutations 20000 --chains 4 --startup-samples 2000 -o "$tmp/me2.lts" --dump-paths "$tmp/me.ltp" --dump-every 100 -q
check "MEMLT's dumped states: lt-inspect --manifold rebuilds and walks their chains" \
    '"$bin/lt-inspect" "$tmp/me.ltp" --manifold | grep -q "walks to themselves converged"'
"$bin/lt-mutate" "$scene" --strategies auto --mutations 2000 --chains 4 --startup-samples 500 -o "$tmp/auto.lts" \
    2> "$tmp/auto-err"
check "auto without specular surfaces: caustic, multi-chain and manifold left out, with the reason" \
    'grep -q "left out: caustic, multi-chain perturbations: no delta" "$tmp/auto-err" &&
     grep -q "left out: manifold perturbation: no delta or glossy" "$tmp/auto-err"'
check "auto without a portal: the portal perturbation left out, with the reason" \
    'grep -q "left out: portal perturbation: no shape marked portal" "$tmp/auto-err"'
"$bin/lt-mutate" "$src/scenes/window-room/scene.xml" --resolution 16x12 --strategies auto --portal-range 0.01,0.1 \
    --mutations 20000 --chains 4 --startup-samples 2000 -o "$tmp/window.lts" 2> "$tmp/window-err"; code=$?
check "auto on a scene with a portal: the portal perturbation runs, its range stored" \
    '[ $code -eq 0 ] && grep -q "^portal " "$tmp/window-err" && ! grep -q "left out: portal" "$tmp/window-err" &&
     "$bin/lt-inspect" "$tmp/window.lts" | grep -q "portal_range"'
"$bin/lt-mutate" "$scene" --strategies bidirectional,portal --mutations 2000 --chains 4 --startup-samples 500 \
    -o "$tmp/noportal.lts" 2> "$tmp/noportal-err"; code=$?
check "the portal perturbation asked for on a scene without a portal: a warning saying it cannot propose" \
    '[ $code -eq 0 ] && grep -q "warning: portal perturbation: no shape marked portal" "$tmp/noportal-err"'
for bad in 0.1 0.2,0.1 0,0.1 0.1,2 nan,0.1; do
    out=$("$bin/lt-mutate" "$scene" --time 1 --portal-range $bad -o "$tmp/x.lts" 2>&1); code=$?
    check "--portal-range $bad refused before any work, naming the option, no output" \
        '[ $code -ne 0 ] && echo "$out" | head -1 | grep -q "portal-range" && [ ! -e "$tmp/x.lts" ]'
done
"$bin/lt-mutate" "$src/scenes/glossy-caustic/scene.xml" --resolution 16x12 --strategies auto --mutations 20000 \
    --chains 4 --startup-samples 2000 -o "$tmp/glossy.lts" 2> "$tmp/glossy-err"; code=$?
check "auto on glossy surfaces: the manifold perturbation with its pre-run, printed and stored" \
    '[ $code -eq 0 ] && grep -q "^manifold " "$tmp/glossy-err" &&
     grep -q "manifold pre-run: 50000 proposals" "$tmp/glossy-err" &&
     "$bin/lt-inspect" "$tmp/glossy.lts" | grep -q "normal_change_degrees"'
check "auto without specular surfaces: the lens perturbation runs" 'grep -q "^lens " "$tmp/auto-err"'
check "auto leaves out the lens-subpath mutation and says how to ask for it" \
    'grep -q "left out: lens-subpath mutation: optional.*--strategies" "$tmp/auto-err"'
"$bin/lt-mutate" "$scene" --mutations 4000 --chains 4 --startup-samples 1000 -o "$tmp/dump.lts" \
    --dump-paths "$tmp/dump.ltp" --dump-every 100 -q; code=$?
check "--dump-paths: exit 0, every 100th state of 4 chains" \
    '[ $code -eq 0 ] && "$bin/lt-inspect" "$tmp/dump.ltp" | grep -q "paths *40,"'
out=$("$bin/lt-mutate" "$scene" --space primary --time 1 --dump-paths "$tmp/x.ltp" --dump-every 10 -o "$tmp/x.lts" 2>&1); code=$?
check "--dump-paths with a primary space: refused" '[ $code -ne 0 ] && echo "$out" | grep -q "needs --space path"'
out=$("$bin/lt-mutate" "$scene" --mutations 100 --dump-paths "$tmp/no/such/dir/d.ltp" --dump-every 10 -o "$tmp/y.lts" 2>&1); code=$?
check "unwritable --dump-paths: one error line naming it, no output" \
    '[ $code -ne 0 ] && echo "$out" | grep -q "no/such/dir" && [ ! -e "$tmp/y.lts" ] && ! ls "$tmp" | grep -q partial'
exit $fail
