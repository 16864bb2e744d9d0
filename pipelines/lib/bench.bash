# The start every benchmark of pipelines/bench shares: the repository root, the build's binaries
# (BUILD_DIR, default build/) and a refusal to run before the build that names the commands.
#   source "$(dirname "${BASH_SOURCE[0]}")/../lib/bench.bash" TOOL     (TOOL: an lt-* binary the script runs)
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
[ -x "$bin/$1" ] || { echo "build first: cmake -S $root -B $root/build && cmake --build $root/build" >&2; exit 1; }
