#!/usr/bin/env bash
# What the tools load: a tool records only the shared libraries it calls (linked --as-needed), and
# OpenImageIO, with its ~250 libraries, comes in only through the image reader module when a scene reads an
# image (libpath/texture/image_file.h). Counted from the dynamic loader's own log, not timed: start-up times
# are measured by pipelines/bench/startup.sh.
#   libraries.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
box="$src/tests/cli/tiny_box.xml"

# The objects the dynamic loader initialised for a command (the executable's libraries and opened modules).
loaded() { LD_DEBUG=libs "$@" 2>&1 >/dev/null | grep "calling init:" | sed 's/.*calling init: //'; }

"$bin/lt-seed" "$box" --spp 1 -o "$tmp/box.lts" -q
loaded "$bin/lt-seed" "$box" --spp 1 -o "$tmp/again.lts" -q > "$tmp/seed.libs"
check "lt-seed of a scene without images loads no OpenImageIO" '! grep -q OpenImageIO "$tmp/seed.libs"'
# Debian's Ceres is a static library: its shared dependencies (glog, SuiteSparse's cholmod) show it.
check "lt-seed loads neither Ceres nor FFTW" '! grep -Eq "libceres|libglog|libcholmod|libfftw" "$tmp/seed.libs"'
check "lt-seed loads Embree (the loader log is read)" 'grep -q libembree "$tmp/seed.libs"'
loaded "$bin/lt-inspect" "$tmp/box.lts" > "$tmp/inspect.libs"
check "lt-inspect of an lt file loads no OpenImageIO" '! grep -q OpenImageIO "$tmp/inspect.libs"'
loaded "$bin/lt-image" "$tmp/box.lts" -o "$tmp/box.exr" --png "$tmp/box.png" > "$tmp/image.libs"
check "lt-image writes EXR and PNG without OpenImageIO" '! grep -q OpenImageIO "$tmp/image.libs" &&
    [ "$(magic "$tmp/box.exr" 4)" = 762f3101 ] && [ "$(magic "$tmp/box.png" 4)" = 89504e47 ]'
loaded "$bin/lt-reconstruct" --help > "$tmp/reconstruct.libs"
check "lt-reconstruct loads Ceres's dependencies and FFTW" 'grep -q libcholmod "$tmp/reconstruct.libs" && grep -q libfftw "$tmp/reconstruct.libs"'

# A scene with an environment map reads an image: the module, and OpenImageIO with it, are loaded then.
loaded "$bin/lt-seed" "$src/scenes/window-room/scene.xml" --resolution 8x8 --spp 1 -o "$tmp/room.lts" -q \
  > "$tmp/room.libs"
check "a scene with an image loads the reader module and OpenImageIO" \
  'grep -q "lt-image-reader.so" "$tmp/room.libs" && grep -q OpenImageIO "$tmp/room.libs"'
check "and renders" '[ -s "$tmp/room.lts" ]'
# A module that does not load (here $LT_MODULE_DIR, searched first, holds a broken one) is skipped for the next.
mkdir -p "$tmp/broken" && echo "not a shared object" > "$tmp/broken/lt-image-reader.so"
LT_MODULE_DIR="$tmp/broken" "$bin/lt-seed" "$src/scenes/window-room/scene.xml" --resolution 8x8 --spp 1 \
  -o "$tmp/room2.lts" -q 2> "$tmp/broken.err"; code=$?
check "a broken module first in the search is skipped" '[ $code -eq 0 ] && [ -s "$tmp/room2.lts" ] && [ ! -s "$tmp/broken.err" ]'
exit $fail
