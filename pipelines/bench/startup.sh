#!/usr/bin/env bash
# Start-up benchmark (report the numbers in the issue note; nothing here is asserted): for trivial jobs of
# each tool, the wall time (median of RUNS runs, default 21), the peak resident memory, the shared
# libraries the dynamic loader maps and the relocations it processes (LD_DEBUG=statistics). Run it on an
# otherwise idle machine.
#   [RUNS=N] pipelines/bench/startup.sh
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-seed
runs="${RUNS:-21}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

box="$root/scenes/cornell-box/scene.xml"
"$bin/lt-seed" "$box" --resolution 16x16 --spp 1 -o "$out/small.lts" -q

# name, then the command line (run from $out).
jobs=(
  "lt-seed --help|$bin/lt-seed --help"
  "lt-inspect small.lts|$bin/lt-inspect small.lts"
  "lt-image small.lts -o x.exr|$bin/lt-image small.lts -o x.exr"
  "lt-image small.lts --png x.png|$bin/lt-image small.lts --png x.png"
  "lt-seed 16x16, 1 spp|$bin/lt-seed $box --resolution 16x16 --spp 1 -o y.lts -q"
  "lt-error small.lts --ref x.exr|$bin/lt-error small.lts --ref x.exr"
  "lt-reconstruct --help|$bin/lt-reconstruct --help"
)

cd "$out"
printf '%-34s %10s %10s %10s %12s\n' job "ms (median)" "peak MB" libraries relocations
for job in "${jobs[@]}"; do
  name="${job%%|*}"; cmd="${job#*|}"
  # Wall time per run by Python's monotonic clock around the process; the median resists a stray slow run.
  ms=$(python3 - "$runs" $cmd <<'PY'
import subprocess, sys, time, statistics
runs, cmd = int(sys.argv[1]), sys.argv[2:]
times = []
for _ in range(runs):
    t = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    times.append((time.perf_counter() - t) * 1000)
print(f"{statistics.median(times):.1f}")
PY
)
  /usr/bin/time -f "%M" -o mem $cmd > /dev/null 2>&1
  # Objects initialised (the executable's libraries and any module it opens) and the final relocation count.
  LD_DEBUG=files,statistics $cmd > /dev/null 2> ld.log || true
  relocs=$(grep "final number of relocations:" ld.log | tail -n 1 | awk '{print $NF}')
  libs=$(grep -c "calling init:" ld.log || true)
  printf '%-34s %10s %10s %10s %12s\n' "$name" "$ms" "$(( $(cat mem) / 1024 ))" "${libs:-?}" "${relocs:-?}"
done
