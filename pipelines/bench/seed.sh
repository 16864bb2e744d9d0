#!/usr/bin/env bash
# Benchmark of lt-seed (report the numbers in the issue note; nothing here is asserted):
# samples/s and rays/s of path tracing and BDPT at 1 and 2 threads, peak memory, and the raw incoherent
# ray rate of the same scene as the bound. Run it on an otherwise idle machine.
#   pipelines/bench/seed.sh [SCENE] [SPP]     (default: scenes/cornell-box/scene.xml, 16 spp)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-seed
scene="${1:-$root/scenes/cornell-box/scene.xml}"
spp="${2:-16}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT


echo "scene: $scene, $spp spp at the scene's resolution, $(nproc) cores"
printf '%-6s %-8s %10s %12s %12s %12s\n' method threads seconds "ksamples/s" "Mrays/s" "peak MB"
for method in pt bdpt; do
  for threads in 1 2; do
    # One thread renders a quarter of the samples so the run stays short; rates are per second.
    s=$spp; [ "$threads" = 1 ] && s=$(( (spp + 3) / 4 ))
    log="$out/$method-$threads.log"
    /usr/bin/time -f "%M" -o "$out/mem" "$bin/lt-seed" "$scene" --method "$method" --spp "$s" --threads "$threads" \
      -o "$out/$method-$threads.lts" 2> "$log"
    line=$(grep -E "spp in" "$log" | tail -n 1)
    secs=$(sed -E 's/.* in ([0-9.]+) s.*/\1/' <<<"$line")
    ksps=$(sed -E 's/.*\(([0-9.e+]+)k samples.*/\1/' <<<"$line")
    mrays=$(sed -E 's/.*, ([0-9.e+]+)M rays.*/\1/' <<<"$line")
    printf '%-6s %-8s %10s %12s %12s %12s\n' "$method" "$threads" "$secs" "$ksps" "$mrays" "$(( $(cat "$out/mem") / 1024 ))"
  done
done
echo
echo "raw closest-hit ray rate (the bound):"
for threads in 1 2; do "$bin/lt-bench-rays" "$scene" --threads "$threads" --rays 20000000; done
