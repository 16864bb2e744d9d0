#!/usr/bin/env bash
# Are two builds' images bit-identical? Renders every scene of scenes/ with every method and option path of the
# render tools (lt-seed, lt-mutate, lt-gradient, lt-reconstruct) at a small size and a fixed amount of work with
# the tools of BIN_A and of BIN_B, then compares each pair of files (pipelines/lib/lt_compare.py: every buffer,
# snapshot, path and chain state bit for bit, the statistics but for times, the INFO parameters). For a change
# that must not change the images (a refactoring, a speed-up that keeps every bit).
#   pipelines/identical.sh BIN_A BIN_B [OUT_DIR]     e.g. pipelines/identical.sh /tmp/old/build/bin build/bin
# SCENES (default: all of scenes/) and RES (default 24) narrow the run; THREADS (default 2). Exits 1 when any
# pair differs or a run fails, naming them.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
[ $# -ge 2 ] || { sed -n '2,9p' "$0" >&2; exit 2; }
bin_a="$(cd "$1" && pwd)"; bin_b="$(cd "$2" && pwd)"
out="${3:-$(mktemp -d "${TMPDIR:-/tmp}/lt-identical.XXXXXX")}"
out="$(mkdir -p "$out" && cd "$out" && pwd)"
res="${RES:-24}"; threads="${THREADS:-2}"
scenes="${SCENES:-$(cd "$root/scenes" && ls -d */ | tr -d /)}"
compare="$root/pipelines/lib/lt_compare.py"
failed=0

# run NAME TOOL ARGS...: the tool of each build writes NAME.* under $out/a and $out/b ("@" in ARGS stands for the
# build's own directory of outputs, so one build's stage reads its own earlier stages).
run() {
  local name="$1" tool="$2"; shift 2
  local status=()
  for side in a b; do
    local bin="$bin_a"; [ "$side" = b ] && bin="$bin_b"
    # Relative names, run from the build's own directory: the parameters a file records are then the same.
    (cd "$out/$side" && "$bin/$tool" "${@//@/.}" -q 2> "$name.err" > /dev/null)
    status+=("$? $(tail -1 "$out/$side/$name.err")")
  done
  # Both builds refusing the same input with the same message is the same behaviour.
  if [ "${status[0]}" != "${status[1]}" ]; then
    echo "DIFFERENT EXIT: $tool $*: A: ${status[0]} | B: ${status[1]}"; failed=1
  elif [ "${status[0]%% *}" != 0 ]; then
    echo "both refused: $tool $*: ${status[0]#* }"
  fi
}

# Every method on one scene: render_all NAME SCENE SIZE_OPTIONS... (--resolution, or -D for a scene's size).
render_all() {
  local s="$1" scene="$2"; shift 2
  local size=("$@" --threads "$threads") common=("$@" --threads "$threads" --seed 7)
  for side in a b; do mkdir -p "$out/$side/$s"; done
  run "$s/bdpt" lt-seed "$scene" "${common[@]}" --spp 4 --snapshot-samples 1,2 -o "@/$s/bdpt.lts" --paths "@/$s/seeds.ltp" --max-paths 4000
  run "$s/bdpt-balance-sobol" lt-seed "$scene" "${common[@]}" --spp 4 --mis balance --sampler sobol --tile 8 -o "@/$s/bdpt-balance-sobol.lts"
  run "$s/pt" lt-seed "$scene" "${common[@]}" --method pt --spp 8 --max-depth 5 --rr-depth 2 -o "@/$s/pt.lts"
  run "$s/pt-sobol" lt-seed "$scene" "${common[@]}" --method pt --spp 8 --sampler sobol -o "@/$s/pt-sobol.lts"
  local chains=(--chains 16 --mutations-per-pixel 8 --round 32)
  run "$s/mlt" lt-mutate "$scene" "@/$s/seeds.ltp" "${common[@]}" "${chains[@]}" --snapshot-mutations 2,4 \
    --dump-paths "@/$s/mlt-dump.ltp" --dump-every 16 -o "@/$s/mlt.lts"
  run "$s/mlt-self" lt-mutate "$scene" "${common[@]}" "${chains[@]}" --startup-samples 3000 --refine-b 0.25 -o "@/$s/mlt-self.lts"
  for m in lens caustic multi-chain lens-subpath manifold hslt portal; do
    run "$s/mlt-$m" lt-mutate "$scene" "@/$s/seeds.ltp" "${common[@]}" "${chains[@]}" --strategies "bidirectional,$m:2" \
      -o "@/$s/mlt-$m.lts"
  done
  run "$s/mlt-options" lt-mutate "$scene" "@/$s/seeds.ltp" "${common[@]}" "${chains[@]}" \
    --strategies bidirectional,manifold,hslt,portal --lambda 200 --hslt-gamma 0.3 --hslt-stratify 0 --hslt-jumps on \
    --portal-range 0.01,0.1 --max-depth 6 -o "@/$s/mlt-options.lts"
  run "$s/pssmlt" lt-mutate "$scene" "${common[@]}" "${chains[@]}" --space primary --startup-samples 3000 \
    --snapshot-mutations 4 -o "@/$s/pssmlt.lts"
  run "$s/mmlt" lt-mutate "$scene" "${common[@]}" "${chains[@]}" --space multiplexed --startup-samples 500 \
    --large-step 0.5 --max-length-unbounded 6 --startup-error 0 -o "@/$s/mmlt.lts"
  run "$s/gdmlt-chains" lt-mutate "$scene" "@/$s/seeds.ltp" "${common[@]}" "${chains[@]}" --target gradient \
    --gradient-alpha 0.3 --stream "@/$s/gdmlt.ltp" -o "@/$s/gdmlt-chains.lts"
  run "$s/gdmlt" lt-gradient "$scene" "${size[@]}" --from-paths "@/$s/gdmlt.ltp" -o "@/$s/gdmlt.lts"
  run "$s/gpt" lt-gradient "$scene" "${common[@]}" --method gpt --spp 4 --snapshot-samples 2 -o "@/$s/gpt.lts"
  run "$s/gdpr" lt-gradient "$scene" "${common[@]}" --spp 4 --tile 4 --rr-delta 0.2 --rr-min 0.2 -o "@/$s/gdpr.lts"
  run "$s/gdpr-l1" lt-reconstruct "@/$s/gdpr.lts" --norm l1 -o "@/$s/gdpr-l1.lts"
  run "$s/gpt-l2" lt-reconstruct "@/$s/gpt.lts" -o "@/$s/gpt-l2.lts"
}

for scene_name in $scenes; do
  render_all "$scene_name" "$root/scenes/$scene_name/scene.xml" --resolution "${res}x$res"
done
# A film with a crop window (which --resolution removes): the estimators and the chains count its pixels only.
cropped="$out/cropped-cornell-spheres.xml"
sed 's|<integer name="height" value="\$res"/>|&<integer name="cropOffsetX" value="5"/><integer name="cropOffsetY" value="3"/><integer name="cropWidth" value="14"/><integer name="cropHeight" value="11"/>|' \
  "$root/scenes/cornell-spheres/scene.xml" > "$cropped"
grep -q cropWidth "$cropped" || { echo "identical.sh: could not add a crop window to cornell-spheres"; exit 1; }
render_all cropped "$cropped" -D "res=$res"

pairs=0
while IFS= read -r f; do
  rel="${f#"$out/a/"}"
  pairs=$((pairs + 1))
  if [ ! -f "$out/b/$rel" ]; then echo "MISSING in B: $rel"; failed=1; continue; fi
  python3 "$compare" "$f" "$out/b/$rel" || failed=1
done < <(find "$out/a" -name '*.lt[sp]' | sort)
echo "identical.sh: $pairs file pairs compared under $out: $([ $failed = 0 ] && echo 'all identical' || echo 'DIFFERENCES above')"
exit $failed
