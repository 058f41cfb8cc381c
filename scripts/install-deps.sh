#!/usr/bin/env bash
# Installs oovr's build and test dependencies from Debian 12's archive.
# Idempotent: asks dpkg what is missing and runs apt-get only for that.
# Usage: scripts/install-deps.sh
set -euo pipefail

packages=(
  # build
  build-essential pkg-config cmake ninja-build ccache clang
  # libraries
  libassimp-dev libstb-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libtomlplusplus-dev libpng-dev zlib1g-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # reference renderer: Mesa llvmpipe through EGL surfaceless
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  # test data: models in OBJ, glTF, PLY and AC3D for the loader tests
  assimp-testmodels
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
