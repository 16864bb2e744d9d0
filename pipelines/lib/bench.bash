# The start every benchmark of pipelines/bench shares: the repository root, the build's binaries
# (BUILD_DIR, default build/) and a refusal to run before the build that names the commands.
#   source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" TOOL     (TOOL: an lt-* binary the script runs)
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
[ -x "$bin/$1" ] || { echo "build first: cmake -S $root -B $root/build && cmake --build $root/build" >&2; exit 1; }

# reference_for SCENE OUT [lt-seed options]: prints the path of a reference image of scenes/SCENE: its shipped
# reference.exr when it has one and no options are given, else OUT/SCENE-reference.exr, rendered first when it is not
# there (pipelines/reference.sh: BDPT for REF_TIME seconds, default 900, with the options, e.g. --resolution; a file
# already there is taken whatever options made it). Fails when the render does: call it as ref="$(reference_for ...)"
# under set -e (errexit is off inside the substitution, so the return status carries the failure).
reference_for() {
  local scene="$1" out="$2"
  shift 2
  if [ $# -eq 0 ] && [ -f "$root/scenes/$scene/reference.exr" ]; then
    echo "$root/scenes/$scene/reference.exr"
    return
  fi
  local ref="$out/$scene-reference.exr"
  [ -f "$ref" ] || bash "$root/pipelines/reference.sh" "$root/scenes/$scene/scene.xml" --time "${REF_TIME:-900}" \
    -o "$ref" "$@" > /dev/null || return 1
  echo "$ref"
}
