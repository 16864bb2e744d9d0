#!/usr/bin/env bash
# lt side by side with a peer renderer (report the numbers in the issue note; nothing here is asserted).
#   [RUNS=3] [SIZE=1024] [METHODS="pt bdpt multiplexed primary"] [SCENES="cornell-box veach-bidir"]
#   pipelines/bench/peers.sh [TUNGSTEN]
# The work: path tracing 16 spp, BDPT 4 spp, multiplexed MLT and primary-sample-space MLT 8 mutations per
# pixel, on scenes/cornell-box at SIZE^2, 1 and 2 threads; and a 16x16, 1-spp render (start-up). For each:
# CPU seconds (user + system, median of RUNS), peak resident memory, and lt's own rates (samples/s,
# mutations/s, rays/s as the tool reports them). veach-bidir gets the same rows for lt alone.
# TUNGSTEN: a Tungsten binary built from source in Release (github.com/tunabrain/tungsten; on processors
# its CPU detection does not know, configure with -DTARGET_ARCHITECTURE=nehalem). Its example scene
# data/example-scenes/cornell-box/scene.json, found beside the build (or given as TUNGSTEN_SCENE), renders
# the same image with fov 19.5 and a square film; max_bounces 65 is lt's maxDepth 65. Runs alternate, lt
# then Tungsten, so that a drift of the machine's speed reaches both; the last column is lt / Tungsten.
# With TUNGSTEN, path tracing and multiplexed MLT (those of METHODS) at equal time as well: EQUAL_TIME seconds
# (default 60; 0 skips it) on 2 threads each, relMSE of both images against scenes/cornell-box/reference.exr
# (lt-error; path tracing with each renderer's independent and its stratified sampler), and each renderer's wall
# time (Tungsten finishes the step of samples it is in when its timeout comes). Tungsten built against
# Debian's OpenEXR 3 writes its HDR image only as PFM (its CMake looks for OpenEXR 2's IlmImf): oiiotool
# (Debian's openimageio-tools) converts it to EXR for lt-error.
# Without TUNGSTEN only lt's figures are printed: run it before and after a change, on an idle machine.
# METHODS and SCENES choose rows (a change to one method need not wait for the others' runs).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" lt-seed
[ -x "$bin/lt-mutate" ] || { echo "peers.sh: $bin/lt-mutate is not built" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "peers.sh: needs GNU time (/usr/bin/time: apt-get install time)" >&2; exit 1; }
runs="${RUNS:-3}"
size="${SIZE:-1024}"
equal_time="${EQUAL_TIME:-60}"
methods="${METHODS:-pt bdpt multiplexed primary}"
scenes="${SCENES:-cornell-box veach-bidir}"
for m in $methods; do
  case "$m" in pt | bdpt | multiplexed | primary) ;; *) echo "peers.sh: unknown method '$m' in METHODS (pt bdpt multiplexed primary)" >&2; exit 2 ;; esac
done
for s in $scenes; do
  [ -f "$root/scenes/$s/scene.xml" ] || { echo "peers.sh: no scene '$s' (SCENES: directories of scenes/)" >&2; exit 2; }
done
tungsten="${1:-}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "peers.sh: RUNS must be a whole number > 0" >&2; exit 2; }
[[ "$size" =~ ^[1-9][0-9]*$ ]] || { echo "peers.sh: SIZE must be a whole number > 0" >&2; exit 2; }
[[ "$equal_time" =~ ^[0-9]+$ ]] || { echo "peers.sh: EQUAL_TIME must be a whole number of seconds" >&2; exit 2; }

if [ -n "$tungsten" ]; then
  [ -x "$tungsten" ] || { echo "peers.sh: $tungsten is not an executable Tungsten binary" >&2; exit 2; }
  if ((equal_time > 0)) && ! command -v oiiotool > /dev/null; then
    echo "peers.sh: the equal-time run needs oiiotool (apt-get install openimageio-tools), or EQUAL_TIME=0" >&2; exit 1
  fi
  scene_json="${TUNGSTEN_SCENE:-}"
  if [ -z "$scene_json" ]; then
    for d in "$(dirname "$tungsten")"/{.,..,../..,../../..}; do
      [ -f "$d/data/example-scenes/cornell-box/scene.json" ] && scene_json="$d/data/example-scenes/cornell-box/scene.json" && break
    done
  fi
  [ -f "$scene_json" ] || { echo "peers.sh: no cornell-box/scene.json beside $tungsten (give TUNGSTEN_SCENE)" >&2; exit 2; }
  # One scene file per method: the example scene with lt's camera and film, the integrator under test,
  # no adaptive sampling, and outputs in $out.
  python3 - "$scene_json" "$out" "$size" <<'PY'
import json, sys
src, out, size = sys.argv[1], sys.argv[2], int(sys.argv[3])
base = json.load(open(src))
base["camera"].update({"resolution": [size, size], "fov": 19.5})
base["renderer"].update({"adaptive_sampling": False, "enable_resume_render": False, "overwrite_output_files": True,
                         "checkpoint_interval": "0", "timeout": "0", "output_file": "render.png",
                         "hdr_output_file": "render.pfm"})
bounces = {"min_bounces": 0, "max_bounces": 65, "enable_light_sampling": True, "enable_two_sided_shading": True}
# The chains at lt's large-step probability (0.3, Mitsuba's; Tungsten's default is 0.1): a large step is a
# fresh path, a small one a perturbation, so the mix sets the work of a mutation.
for name, integrator in {"pt": {"type": "path_tracer"}, "bdpt": {"type": "bidirectional_path_tracer"},
                         "multiplexed": {"type": "multiplexed_mlt", "large_step_probability": 0.3},
                         "primary": {"type": "kelemen_mlt", "bidirectional": True,
                                     "large_step_probability": 0.3}}.items():
    scene = dict(base)
    scene["integrator"] = dict(bounces, **integrator)
    # Every shape of the example is inline (quads and cubes): the files need no directory of their own.
    json.dump(scene, open(f"{out}/tungsten-{name}.json", "w"), indent=1)
PY
fi

# CPU seconds and peak MB of one command: "CPU PEAK" (its output to $out/log). A failure stops the script
# with the command and its output.
measure() {
  if ! /usr/bin/time -f "%U %S %M" -o "$out/time" "$@" > "$out/log" 2>&1; then
    echo "peers.sh: failed: $*" >&2; cat "$out/log" >&2; exit 1
  fi
  awk '{printf "%.2f %d\n", $1 + $2, $3 / 1024}' "$out/time"
}
# Tungsten exits with 0 when a scene fails to load or render: a run counts only if it wrote its image.
measure_tungsten() {
  rm -f "$out/tungsten/render.png"
  measure "$@"
  if [ ! -f "$out/tungsten/render.png" ] || grep -q "unrecoverable error" "$out/log"; then
    echo "peers.sh: Tungsten did not render: $*" >&2; cat "$out/log" >&2; exit 1
  fi
}
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# lt's own rate, from the tool's last line: "(307k samples/s, 1.97M rays/s)" (3 significant digits, so
# "1.23e+03k" past a million).
rates() {
  { grep -oE '\([0-9.e+]+k (samples|mutations)/s, [0-9.e+]+M rays/s\)' "$out/log" || true; } | tail -1 | tr -d '()'
}

# The command of one run, into the array cmd.
lt_command() { # METHOD THREADS SCENE
  case "$1" in
    pt | bdpt)
      local spp=16; [ "$1" = bdpt ] && spp=4
      cmd=("$bin/lt-seed" "$3" --method "$1" --spp "$spp" --resolution "${size}x$size" --threads "$2" -o "$out/lt.lts") ;;
    multiplexed | primary)
      cmd=("$bin/lt-mutate" "$3" --space "$1" --mutations-per-pixel 8 --resolution "${size}x$size" --threads "$2"
        -o "$out/lt.lts") ;;
  esac
}
tungsten_command() { # METHOD THREADS
  local spp=16
  case "$1" in bdpt) spp=4 ;; multiplexed | primary) spp=8 ;; esac
  cmd=("$tungsten" -t "$2" --spp "$spp" -s 1 -d "$out/tungsten" "$out/tungsten-$1.json")
}

echo "$runs runs each, ${size}x$size, $(nproc) cores, $(date -u +%FT%TZ), lt $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?')"
for scene in $scenes; do
  xml="$root/scenes/$scene/scene.xml"
  echo
  echo "== $scene"
  peer=0; [ -n "$tungsten" ] && [ "$scene" = cornell-box ] && peer=1
  if ((peer)); then
    printf '%-12s %3s %9s %8s %-30s %12s %10s %8s\n' work thr "lt CPU s" "lt MB" "lt rate" "Tungsten s" "Tung. MB" "lt/Tung."
  else
    printf '%-12s %3s %9s %8s %-30s\n' work thr "lt CPU s" "lt MB" "lt rate"
  fi
  for method in $methods; do
    for threads in 1 2; do
      : > "$out/lt.cpu"; : > "$out/tu.cpu"; ltmb=0; tumb=0; rate=""
      for ((r = 0; r < runs; ++r)); do
        lt_command "$method" "$threads" "$xml"
        measure "${cmd[@]}" > "$out/m"; read -r cpu mb < "$out/m"
        echo "$cpu" >> "$out/lt.cpu"; if ((mb > ltmb)); then ltmb=$mb; fi; rate=$(rates)
        if ((peer)); then
          tungsten_command "$method" "$threads"
          measure_tungsten "${cmd[@]}" > "$out/m"; read -r cpu mb < "$out/m"
          echo "$cpu" >> "$out/tu.cpu"; if ((mb > tumb)); then tumb=$mb; fi
        fi
      done
      lt=$(median < "$out/lt.cpu")
      if ((peer)); then
        tu=$(median < "$out/tu.cpu")
        printf '%-12s %3s %9s %8s %-30s %12s %10s %8s\n' "$method" "$threads" "$lt" "$ltmb" "$rate" "$tu" "$tumb" \
          "$(awk -v a="$lt" -v b="$tu" 'BEGIN {if (b > 0) printf "%.2fx", a / b; else printf "-"}')"
      else
        printf '%-12s %3s %9s %8s %-30s\n' "$method" "$threads" "$lt" "$ltmb" "$rate"
      fi
    done
  done
done

# Start-up: wall milliseconds (median of 21 runs) and peak memory of a trivial render.
echo
echo "== start-up: a 16x16, 1-spp path-traced render (wall ms, median of 21; peak MB)"
startup() { # COMMAND...
  python3 - "$@" <<'PY'
import subprocess, sys, time, statistics
times = []
for _ in range(21):
    t = time.perf_counter()
    subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    times.append((time.perf_counter() - t) * 1000)
print(f"{statistics.median(times):.1f}")
PY
}
box="$root/scenes/cornell-box/scene.xml"
lt_small=("$bin/lt-seed" "$box" --resolution 16x16 --spp 1 --threads 1 -q -o "$out/small.lts")
printf '%-10s %8s ms %6s MB\n' lt "$(startup "${lt_small[@]}")" "$(measure "${lt_small[@]}" | cut -d' ' -f2)"
if [ -n "$tungsten" ]; then
  python3 - "$out/tungsten-pt.json" "$out/tungsten-small.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["camera"]["resolution"] = [16, 16]
json.dump(scene, open(sys.argv[2], "w"))
PY
  tu_small=("$tungsten" -t 1 --spp 1 -s 1 -d "$out/tungsten" "$out/tungsten-small.json")
  printf '%-10s %8s ms %6s MB\n' Tungsten "$(startup "${tu_small[@]}")" "$(measure_tungsten "${tu_small[@]}" | cut -d' ' -f2)"
fi

# Path tracing and multiplexed MLT at equal time: relMSE against the reference (Tungsten's bare "timeout"
# number means minutes).
if [ -n "$tungsten" ] && ((equal_time > 0)); then
  reference="$root/scenes/cornell-box/reference.exr"
  for method in pt multiplexed; do
    [[ " $methods " == *" $method "* ]] || continue
    echo
    echo "== $method for ${equal_time} s on 2 threads, cornell-box ${size}x$size: relMSE against $reference"
    python3 - "$out/tungsten-$method.json" "$out/tungsten-timed.json" "$equal_time" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
# Tungsten checks its timeout between steps of spp_step samples per pixel (16 in the example scene, which
# overran a 3 s timeout to 16 s at 1024^2): one spp (MLT: one mutation per pixel) per step keeps its time
# close to lt's.
scene["renderer"].update({"timeout": f"{sys.argv[3]}s", "spp": 1 << 20, "spp_step": 1})
json.dump(scene, open(sys.argv[2], "w"))
PY
    if [ "$method" = pt ]; then
      # Like with like: lt's independent numbers against Tungsten's uniform sampler (the example scene's
      # "stratified_sampler": false), and lt's Sobol sampler against Tungsten's (true).
      images=()
      for sampler in independent sobol; do
        measure "$bin/lt-seed" "$box" --method pt --sampler "$sampler" --time "$equal_time" \
          --resolution "${size}x$size" --threads 2 -o "$out/timed-$sampler.lts" > /dev/null
        echo "lt, $sampler: $(tail -1 "$out/log")"
        images+=("$out/timed-$sampler.lts")
      done
      for stratified in false true; do
        python3 - "$out/tungsten-timed.json" "$stratified" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["renderer"]["stratified_sampler"] = sys.argv[2] == "true"
json.dump(scene, open(sys.argv[1], "w"))
PY
        measure_tungsten "$tungsten" -t 2 -s 1 -d "$out/tungsten" "$out/tungsten-timed.json" > /dev/null
        echo "Tungsten, stratified_sampler $stratified: $(grep -o 'Render time.*' "$out/log" | tail -1)"
        [ -f "$out/tungsten/render.pfm" ] || { echo "peers.sh: Tungsten wrote no render.pfm" >&2; exit 1; }
        oiiotool "$out/tungsten/render.pfm" -o "$out/tungsten-stratified-$stratified.exr"
        images+=("$out/tungsten-stratified-$stratified.exr")
      done
      "$bin/lt-error" --ref "$reference" "${images[@]}"
      continue
    fi
    measure "$bin/lt-mutate" "$box" --space "$method" --time "$equal_time" --resolution "${size}x$size" --threads 2 \
      -o "$out/timed.lts" > /dev/null
    echo "lt: $(tail -1 "$out/log")"
    measure_tungsten "$tungsten" -t 2 -s 1 -d "$out/tungsten" "$out/tungsten-timed.json" > /dev/null
    echo "Tungsten: $(grep -o 'Render time.*' "$out/log" | tail -1)"
    [ -f "$out/tungsten/render.pfm" ] || { echo "peers.sh: Tungsten wrote no render.pfm" >&2; exit 1; }
    oiiotool "$out/tungsten/render.pfm" -o "$out/tungsten.exr"
    "$bin/lt-error" --ref "$reference" "$out/timed.lts" "$out/tungsten.exr"
  done
fi
