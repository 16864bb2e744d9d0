#!/usr/bin/env bash
# Runs one libFuzzer harness of tests/fuzz on its committed corpus and prints what it did.
#   pipelines/fuzz.sh [--no-build] TARGET SECONDS [LIBFUZZER_OPTION ...]
#   pipelines/fuzz.sh --list
# TARGET: ltfile, scene, obj-loader, ply-loader, serialized-loader, gradient-input (tests/fuzz/NAME_fuzzer.cpp
# with _ as -). Builds the harness first in BUILD_DIR (default build-fuzz/: clang, -DLT_FUZZ=ON, which also turns
# on ASan and UBSan) unless --no-build (CTest's runs). The committed corpus tests/fuzz/corpus/TARGET is only read:
# what the run finds new goes to BUILD_DIR/fuzz-runs/TARGET/corpus (kept, so a later run goes on from it), and an
# input that crashes, leaks, hangs past FUZZ_TIMEOUT seconds (default 10) or allocates more than FUZZ_RSS_MB
# (default 2048) to BUILD_DIR/fuzz-runs/TARGET/findings (kept; the summary counts this run's). Exit status:
# libFuzzer's (0: no finding). Inputs are written under TMPDIR (default /dev/shm when writable).
# Long runs on both cores: pipelines/fuzz.sh scene 3600 -fork=2 -ignore_crashes=1
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build-fuzz}"
fuzz="$root/tests/fuzz"

targets() { for f in "$fuzz"/*_fuzzer.cpp; do f="${f##*/}"; f="${f%_fuzzer.cpp}"; echo "${f//_/-}"; done; }

usage() { sed -n 2,12p "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }

build_first=1
case "${1:-}" in
  --list) targets; exit 0 ;;
  --no-build) build_first=0; shift ;;
  -h|--help) usage ;;
esac
[ $# -ge 2 ] || usage
target="$1" seconds="$2"
shift 2
targets | grep -x -- "$target" >/dev/null || { echo "fuzz.sh: no harness '$target' (targets: $(targets | tr '\n' ' '))" >&2; exit 2; }
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: SECONDS must be a whole number > 0, got '$seconds'" >&2; exit 2; }

binary="$build/bin/fuzz-$target"
if ((build_first)); then
  "$root/pipelines/install-deps.sh" >/dev/null
  if [ ! -f "$build/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLT_FUZZ=ON >/dev/null
  fi
  cmake --build "$build" -j "$(nproc)" --target "fuzz-$target"
fi
[ -x "$binary" ] || { echo "fuzz.sh: $binary is not built (run without --no-build)" >&2; exit 1; }

runs="$build/fuzz-runs/$target"
mkdir -p "$runs/corpus" "$runs/findings"
dict=()
[ -f "$fuzz/$target.dict" ] && dict=("-dict=$fuzz/$target.dict")
log="$runs/log.txt"
touch "$log.start" # findings of this run are the files newer than it
# The harnesses write each input to a file under TMPDIR for the readers (tests/fuzz/fuzz_input.h). On a disk
# that costs a file creation per execution: measured here, /tmp on ext4 kept a plain-mode run at about 40 %
# of a core in I/O wait, /dev/shm (memory) at 100 %. Memory is the default when there is one to write to.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
status=0
"$binary" "$runs/corpus" "$fuzz/corpus/$target" "${dict[@]}" -max_total_time="$seconds" \
  -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb="${FUZZ_RSS_MB:-2048}" -print_final_stats=1 \
  -artifact_prefix="$runs/findings/" "$@" > "$log" 2>&1 || status=$?

# libFuzzer's last status line ("#N DONE cov: C ft: F corp: K/..", with -fork "#N: cov: C ft: F corp: K ...") and
# its final statistics (not printed with -fork: there N counts the executions).
last=$(grep -E '^#[0-9]+:?[[:space:]].*cov: ' "$log" | tail -1 || true)
execs=$({ grep -oE 'stat::number_of_executed_units: [0-9]+' "$log" || true; } | awk '{s += $2} END {print s + 0}')
((execs > 0)) || execs=$(sed -nE 's/^#([0-9]+).*/\1/p' <<< "$last")
cov=$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<< "$last")
ft=$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<< "$last")
corp=$(sed -nE 's/.* corp: ([0-9]+).*/\1/p' <<< "$last")
findings=$(find "$runs/findings" -type f -newer "$log.start" | wc -l)
echo "fuzz $target: $execs executions in $seconds s, coverage ${cov:-?} edges (${ft:-?} features), corpus ${corp:-?}," \
  "findings: $findings (in $runs/findings), exit $status"
if ((status != 0)); then
  echo "fuzz $target: the end of $log:" >&2
  tail -40 "$log" >&2
fi
exit "$status"
