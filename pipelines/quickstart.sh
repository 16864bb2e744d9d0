#!/usr/bin/env bash
# From a fresh Debian machine to a described (and, once lt-seed exists, rendered) default scene:
# installs missing packages, builds in Release, runs the default scene through the tools and prints
# where the results are.
#   pipelines/quickstart.sh [SCENE]      (default: scenes/cornell-spheres/scene.xml)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
scene="${1:-$root/scenes/cornell-spheres/scene.xml}"
out="${OUT_DIR:-$root/out/quickstart}"

"$root/pipelines/install-deps.sh"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)"
bin="$build/bin"
mkdir -p "$out"

echo
echo "== lt-inspect $scene"
"$bin/lt-inspect" "$scene" | tee "$out/inspect.txt"
"$bin/lt-inspect" "$scene" --json > "$out/inspect.json"

if [ -x "$bin/lt-seed" ] && [ -x "$bin/lt-image" ]; then
  echo
  echo "== lt-seed (BDPT) and lt-image"
  "$bin/lt-seed" "$scene" -o "$out/seed.lts"
  "$bin/lt-image" "$out/seed.lts" -o "$out/seed.exr" --png "$out/seed.png"
  echo
  echo "images: $out/seed.exr (linear), $out/seed.png (sRGB preview)"
else
  echo
  echo "No renderer is built yet (lt-seed arrives with the next milestone): the scene summary is in"
  echo "  $out/inspect.txt and $out/inspect.json"
fi
