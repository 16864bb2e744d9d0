#!/usr/bin/env bash
# Benchmark of lt-mutate (report the numbers in the issue note; nothing here is asserted): mutations/s,
# rays/s and acceptance per strategy for each chain space, at 1 and 2 threads, with peak memory. Run it
# on an otherwise idle machine.
#   [SPACES="path primary multiplexed"] pipelines/bench/mutate.sh [SECONDS] [SCENE...]
#   (default: 20 s, all three spaces; scenes/cornell-box and scenes/veach-bidir)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-mutate
seconds="${1:-20}"; shift || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=("$root/scenes/cornell-box/scene.xml" "$root/scenes/veach-bidir/scene.xml")
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

echo "$seconds s per run (start-up included), scene resolution, $(nproc) cores"
for scene in "${scenes[@]}"; do
  echo
  echo "== $scene"
  for space in ${SPACES:-path primary multiplexed}; do
    for threads in 1 2; do
      log="$out/$space-$threads.log"
      /usr/bin/time -f "%M" -o "$out/mem" "$bin/lt-mutate" "$scene" --space "$space" --time "$seconds" \
        --threads "$threads" -o "$out/run.lts" 2> "$log"
      echo "-- $space, $threads thread(s), peak $(( $(cat "$out/mem") / 1024 )) MB"
      # The end-of-run report: b, the per-strategy table, chains per length, the rates.
      grep -v -E "^lt-mutate (start-up|[0-9.]+ mutations/pixel, )" "$log" | grep -v "^\s*$" | tr '\r' '\n' | \
        grep -v -E "^lt-mutate \[" || true
    done
  done
done
