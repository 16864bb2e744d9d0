#!/usr/bin/env bash
# Install the Debian packages lt needs, if any is missing. Used by tests/run.sh and
# pipelines/quickstart.sh; safe to run again (it only installs what dpkg does not report installed).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libembree-dev libtbb-dev          # ray tracing
  libopenexr-dev libpng-dev         # final images: EXR, PNG preview
  libopenimageio-dev                # bitmap textures (a module loaded on demand)
  libceres-dev libeigen3-dev        # Poisson reconstruction, small dense/sparse algebra
  libfftw3-dev                      # cosine-transform Poisson solver of large reconstructions
  libcli11-dev nlohmann-json3-dev   # command lines, JSON
  libpugixml-dev libtinyobjloader-dev zlib1g-dev   # scene XML, meshes, Mitsuba .serialized
  catch2                            # tests
  clang libclang-rt-14-dev          # sanitizer and fuzz builds: tests/run.sh --sanitize, pipelines/fuzz.sh
  python3-matplotlib python3-numpy  # plots in pipelines/
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
