#!/usr/bin/env bash
# lt-reconstruct from the command line: a synthetic noisy gradient-domain buffer (lt-bench-gradient-input)
# reconstructed to a cleaner image than its primal, the same result from an lt buffer file, a multi-layer
# EXR, separate --primal/--dx/--dy files and a pipe; one error line, a non-zero exit and no output file
# for every bad input.
#   lt_reconstruct.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
# stat_row FILE ROW: the value of ROW in FILE's STAT table "reconstruct"
stat_row() { "$bin/lt-inspect" "$1" --json | python3 -c "
import json, sys
t = [s for s in json.load(sys.stdin)['stats'] if s['name'] == 'reconstruct'][0]
print('%g' % dict(zip(t['rows'], [r[0] for r in t['values']]))[sys.argv[1]])" "$2"; }
# mse FILE REF: lt-error's MSE of FILE against REF
mse() { "$bin/lt-error" "$1" --ref "$2" --metric mse --csv mse.csv > /dev/null 2>&1 && awk -F, 'NR == 2 { print $7 }' mse.csv; }
"$bin/lt-bench-gradient-input" --width 48 --height 32 --noise 0.2 --gradient-noise 0.02 -o in.lts --truth truth.exr
check "input made" '[ -s in.lts ] && [ -s truth.exr ]'

out=$("$bin/lt-reconstruct" in.lts -o l2.lts 2>&1); code=$?
echo "$out"
check "L2: exit 0 and statistics on stderr" '[ $code -eq 0 ] &&
  echo "$out" | grep -Eq "^lt-reconstruct: l2, alpha 0.2, 48x32: 3 solves with SPARSE_NORMAL_CHOLESKY \(auto: 1536 <= 4096 pixels\), 3 iterations, .* s; wrote l2.lts$"'
check "L2: STAT table reconstruct in the file" '"$bin/lt-inspect" l2.lts --json | python3 -c "
import json, sys
j = json.load(sys.stdin)
t = [s for s in j[\"stats\"] if s[\"name\"] == \"reconstruct\"][0]
v = dict(zip(t[\"rows\"], [r[0] for r in t[\"values\"]]))
assert v[\"norm\"] == 2 and v[\"alpha\"] == 0.2 and v[\"final_cost\"] < v[\"initial_cost\"], v
assert j[\"buffers\"][0][\"channels\"] == [\"R\", \"G\", \"B\"], j[\"buffers\"]
"'
# The primal alone: alpha so large that the result is the primal (relative weight 1e-8 on the gradients).
"$bin/lt-reconstruct" in.lts --alpha 1e4 -o primal.exr -q
el2=$(mse l2.lts truth.exr)
ep=$(mse primal.exr truth.exr)
# Gradients with a tenth of the primal's noise: the reconstruction must have much less error than the
# primal (a factor 4 is a wide margin).
check "L2 beats the primal ($el2 vs $ep)" 'awk -v a="$el2" -v b="$ep" "BEGIN { exit !(a > 0 && a < b / 4) }"'

out=$("$bin/lt-reconstruct" in.lts --norm l1 --iterations 5 -o l1.exr 2>&1); code=$?
check "L1: exit 0, EXR written, 5 IRLS steps and the mean's restoration" '[ $code -eq 0 ] &&
  [ "$(magic l1.exr 4)" = "762f3101" ] &&
  echo "$out" | grep -q "^lt-reconstruct: l1, alpha 0.2, 48x32: 5 IRLS steps, 15 solves" &&
  echo "$out" | grep -Eq "; mean [-+][0-9.]+ % from the primal.s, restored over 16 px \(3 solves with SPARSE_NORMAL_CHOLESKY\) to [-+]0.00 %; "'
# The mean's shift and its restoration in the STAT table; --mean free leaves the minimizer as it is.
"$bin/lt-reconstruct" in.lts --norm l1 --iterations 5 --mean-scale 4 -o l1.lts -q
out=$("$bin/lt-reconstruct" in.lts --norm l1 --iterations 5 --mean free -o l1free.lts 2>&1); code=$?
check "L1: the mean in STAT, kept over --mean-scale by default, free on request" '[ $code -eq 0 ] &&
  [ "$(stat_row l1.lts mean_scale)" = 4 ] && [ "$(stat_row l1free.lts mean_scale)" = 0 ] &&
  awk -v a="$(stat_row l1.lts mean_shift)" "BEGIN { exit !(a < 1e-6 && a > -1e-6) }" &&
  [ "$(stat_row l1free.lts mean_shift)" = "$(stat_row l1free.lts mean_shift_solve)" ] &&
  echo "$out" | grep -q "15 solves" && ! echo "$out" | grep -q restored'
out=$("$bin/lt-reconstruct" in.lts --norm l1 --mean-scale 0 -o bad.lts 2>&1); code=$?
check "--mean-scale 0 is refused" '[ $code -ne 0 ] && [ ! -e bad.lts ]'

# Eigen CG on request gives the exact solve's image to its tolerance (relative residual 1e-5: an MSE
# far below 1e-8 on values near 1) and is named in the statistics and the STAT table (solver code 3).
out=$("$bin/lt-reconstruct" in.lts --solver eigen-cg -o cg.lts 2>&1); code=$?
ecg=$(mse cg.lts l2.lts)
check "eigen-cg: exit 0, named with its reason and residual, same image (mse $ecg)" '[ $code -eq 0 ] &&
  echo "$out" | grep -Eq "^lt-reconstruct: l2, alpha 0.2, 48x32: 3 solves with EIGEN_CG \(requested\), 3 iterations, [0-9]+ linear solver iterations, relative residual <= " &&
  awk -v e="$ecg" "BEGIN { exit !(e < 1e-8) }" &&
  [ "$(stat_row cg.lts solver)" = 3 ]'
# auto takes DCT for L2 and Eigen CG for L1 above 64x64 pixels and says why.
"$bin/lt-bench-gradient-input" --width 80 --height 60 -o big.lts
out=$("$bin/lt-reconstruct" big.lts -o big.exr 2>&1); code=$?
check "auto: dct for L2 above 4096 pixels" '[ $code -eq 0 ] &&
  echo "$out" | grep -q "3 solves with DCT (auto: 4800 > 4096 pixels, l2), 3 iterations, 3 linear solver iterations, relative residual <= "'
out=$("$bin/lt-reconstruct" big.lts --norm l1 --iterations 2 -o big.exr 2>&1); code=$?
check "auto: eigen-cg for L1 above 4096 pixels" '[ $code -eq 0 ] &&
  echo "$out" | grep -q "6 solves with EIGEN_CG (auto: 4800 > 4096 pixels, l1)" &&
  echo "$out" | grep -q "restored over 16 px (3 solves with DCT)"'
# DCT on request: the exact solve's image (float output: MSE far below 1e-12 on values near 1), solver
# code 4 in the STAT table.
out=$("$bin/lt-reconstruct" in.lts --solver dct -o dct.lts 2>&1); code=$?
edct=$(mse dct.lts l2.lts)
check "dct: exit 0, named, same image as Cholesky (mse $edct)" '[ $code -eq 0 ] &&
  echo "$out" | grep -Eq "^lt-reconstruct: l2, alpha 0.2, 48x32: 3 solves with DCT \(requested\), 3 iterations, 3 linear solver iterations, relative residual <= " &&
  awk -v e="$edct" "BEGIN { exit !(e < 1e-12) }" &&
  [ "$(stat_row dct.lts solver)" = 4 ]'

# The same input as a multi-layer EXR, as separate files (each file's primal, dx, dy layer) and on a pipe.
"$bin/lt-image" in.lts -o layers.exr 2>/dev/null
"$bin/lt-reconstruct" layers.exr -o from_exr.exr -q; c1=$?
"$bin/lt-reconstruct" --primal layers.exr --dx layers.exr --dy layers.exr -o from_files.exr -q; c2=$?
"$bin/lt-reconstruct" - -o - -q < in.lts > piped.lts; c3=$?
check "multi-layer EXR, separate files, pipe: exit 0" '[ $c1 -eq 0 ] && [ $c2 -eq 0 ] && [ $c3 -eq 0 ]'
for f in from_exr.exr from_files.exr piped.lts; do
  e=$(mse "$f" l2.lts)
  check "$f equals the buffer file's result (mse $e)" '[ "$e" = "0" ]'
done

# Bad input: exactly one line, a non-zero exit, no output file and no temporary file.
bad() {  # NAME EXPECTED-LINE ARGS...
  local name="$1" expected="$2"; shift 2
  rm -f bad.lts bad.exr
  out=$("$bin/lt-reconstruct" "$@" 2>&1); code=$?
  check "$name: one error line, non-zero exit, no output" '[ $code -ne 0 ] && [ "$out" = "$expected" ] &&
    [ ! -e bad.lts ] && [ ! -e bad.exr ] && [ -z "$(ls | grep partial)" ] || { echo "got ($code): $out"; false; }'
}
bad "alpha 0" "lt-reconstruct: error: alpha must be positive and finite, got 0.000000" in.lts --alpha 0 -o bad.lts
bad "alpha < 0" "lt-reconstruct: error: alpha must be positive and finite, got -1.000000" in.lts --alpha -1 -o bad.exr
bad "missing layers" "lt-reconstruct: error: truth.exr: no layer 'primal' (channels primal.R/G/B); it has R, G, B" \
  truth.exr -o bad.lts
"$bin/lt-bench-gradient-input" --width 8 --height 8 -o small.lts
"$bin/lt-image" small.lts -o small.exr 2>/dev/null
bad "mismatched sizes" "lt-reconstruct: error: small.exr: 8x8 does not match the primal layers.exr (48x32)" \
  --primal layers.exr --dx small.exr --dy layers.exr -o bad.exr
"$bin/lt-bench-gradient-input" --width 8 --height 8 --noise nan -o nan.lts
bad "NaN in the primal" "lt-reconstruct: error: nan.lts: channel primal.R is NaN at pixel (0, 0)" nan.lts -o bad.lts
"$bin/lt-bench-gradient-input" --width 8 --height 8 --gradient-noise inf -o inf.lts
bad "Inf in a gradient" "lt-reconstruct: error: inf.lts: channel dx.R is infinite at pixel (0, 0)" inf.lts -o bad.exr
bad "unreadable file" "lt-reconstruct: error: nothere.lts: cannot open (No such file or directory)" nothere.lts -o bad.lts
head -c 200 in.lts > cut.lts
out=$("$bin/lt-reconstruct" cut.lts -o bad.lts 2>&1); code=$?
check "truncated file: one error line naming it" '[ $code -ne 0 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] &&
  [[ "$out" == "lt-reconstruct: error: cut.lts: truncated"* ]] && [ ! -e bad.lts ]'
bad "no input" "lt-reconstruct: error: no input: give IN, or --primal, --dx and --dy" -o bad.lts

check "--help explains the conventions" '"$bin/lt-reconstruct" --help | grep -q "forward differences" &&
  "$bin/lt-reconstruct" --help | grep -q "enters the L2 objective squared" &&
  "$bin/lt-reconstruct" --help | grep -q "eigen-cg" && "$bin/lt-reconstruct" --help | grep -q "dct"'

# SIGTERM while snapshots stream in: the stream is left after the snapshot under way, its newest buffer reconstructed.
"$bin/lt-gradient" "$src/tests/cli/tiny_box.xml" --method gpt --time 4 --snapshots 0.25,0.5,0.75,1,1.5,2,2.5,3,3.5 \
  -o - -q | "$bin/lt-reconstruct" - -o term.lts -q & pid=$!
sleep 2; kill -TERM $pid; wait $pid; code=$?
check "SIGTERM: exit code 143, a complete file, later snapshots left out" \
  '[ $code -eq 143 ] && [ "$(tail -c 16 term.lts | head -c 4)" = "END!" ] && chunks term.lts | grep -q "^BUFR" &&
   n=$(chunks term.lts | grep -c "^SNAP") && [ "$n" -ge 1 ] && [ "$n" -lt 9 ]'

exit $fail
