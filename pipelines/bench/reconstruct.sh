#!/usr/bin/env bash
# Benchmark of lt-reconstruct: a synthetic noisy 1280x720 RGB gradient-domain buffer (lt-bench-gradient-input),
# reconstructed with L2 and L1 on 1 and 2 threads, then a 3840x2160 (4K) input with L2 on 2 threads; prints
# wall time (reading and writing included), peak memory (GNU time's maximum resident set size) and the
# error against the noise-free image next to the primal's. The solver is auto's at these sizes: the exact
# cosine-transform solve (DCT) for L2, Eigen CG for L1; SOLVER=eigen-cg (or dct, cgnr, cholesky) forces one.
#   [SOLVER=S] pipelines/bench/reconstruct.sh [BUILD_DIR] [WIDTH HEIGHT]      (default: build, 1280 720)
set -euo pipefail
build="${1:-build}"; width="${2:-1280}"; height="${3:-720}"; solver="${SOLVER:-auto}"
bin="$build/bin"
for t in lt-bench-gradient-input lt-reconstruct lt-error; do
  [ -x "$bin/$t" ] || { echo "reconstruct.sh: $bin/$t not built" >&2; exit 1; }
done
[ -x /usr/bin/time ] || { echo "reconstruct.sh: needs GNU time (/usr/bin/time, Debian package time)" >&2; exit 1; }

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# make_input WIDTH HEIGHT: $tmp/in.lts and the noise-free $tmp/truth.exr
make_input() {
  "$bin/lt-bench-gradient-input" --width "$1" --height "$2" --noise 0.2 --gradient-noise 0.05 \
    --outliers 1e-4 --outlier-value 100 -o "$tmp/in.lts" --truth "$tmp/truth.exr"
}
mse() { "$bin/lt-error" "$1" --ref "$tmp/truth.exr" --metric mse --csv "$tmp/mse.csv" > /dev/null 2>&1 && awk -F, 'NR == 2 { print $7 }' "$tmp/mse.csv"; }
# run NORM THREADS LABEL: one reconstruction of $tmp/in.lts, one table row and the tool's statistics line
run() {
  /usr/bin/time -v -o "$tmp/time.txt" "$bin/lt-reconstruct" "$tmp/in.lts" --norm "$1" --threads "$2" \
    --solver "$solver" -o "$tmp/out.exr" 2> "$tmp/log.txt"
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, t, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + t[i]; print s }' "$tmp/time.txt")
  rss=$(awk -F': ' '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$tmp/time.txt")
  printf '%-10s %-5s %-8s %10s %14s %12s\n' "$3" "$1" "$2" "$wall" "$rss" "$(mse "$tmp/out.exr")"
  grep '^lt-reconstruct: l' "$tmp/log.txt" | sed 's/^/      /'
}

make_input "$width" "$height"
# The primal alone, for comparison: with alpha = 1e4 the gradients weigh 1e-8 of the primal.
"$bin/lt-reconstruct" "$tmp/in.lts" --alpha 1e4 --max-solver-iterations 5 -o "$tmp/primal.exr" -q
echo "input: RGB, primal noise 0.2, gradient noise 0.05, 1e-4 of the gradients +-100; ${width}x${height} primal mse $(mse "$tmp/primal.exr")"
printf '%-10s %-5s %-8s %10s %14s %12s\n' size norm threads "wall [s]" "peak RSS [MB]" mse
for norm in l2 l1; do
  for threads in 1 2; do
    run "$norm" "$threads" "${width}x${height}"
  done
done
# 4K: the memory bound (DCT: no matrix, a right-hand side and the solution per channel in double; Eigen
# CG: a 64-byte-per-pixel matrix and a few vectors per channel).
make_input 3840 2160
run l2 2 3840x2160
