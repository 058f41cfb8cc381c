#!/usr/bin/env bash
# Installs oovr's build and test dependencies from Debian 12's archive.
# Idempotent: asks dpkg what is missing and runs apt-get only for that.
#
# Usage: scripts/install-deps.sh [--game-data] [--services] [--capture]
#   --game-data  also install the real game levels used as workloads:
#                OpenArena maps and textures (about 410 MB), Nexuiz
#                (nexuiz-data, about 800 MB) and TORCS tracks (about
#                530 MB). Tests that need them report "skipped" without
#                them; CI installs them.
#   --services   also install what the cluster and browser tests start:
#                SLURM (slurmctld, slurmd and the client commands, for
#                `oovr sweep --backend slurm`) and Chromium (to open
#                `oovr report`'s page headless). Without them those tests
#                report "skipped"; CI installs them.
#   --capture    also install what captures a real game's frames
#                (scripts/capture-frames.sh, the round-trip test):
#                apitrace, Xvfb, OpenArena's engine and Nexuiz's
#                (DarkPlaces; its data is --game-data's). CI installs them.
set -euo pipefail

packages=(
  # build
  build-essential pkg-config cmake ninja-build ccache
  # clang and its runtime for the sanitizer and libFuzzer build;
  # clang-format for the style check (.clang-format)
  clang libclang-rt-14-dev clang-format
  # libraries
  libassimp-dev libstb-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libtomlplusplus-dev libpng-dev zlib1g-dev libpugixml-dev
  # apitrace's trace files (real game frames) are snappy-compressed
  libsnappy-dev
  # the results database (and its command-line shell, for queries and tests)
  libsqlite3-dev sqlite3
  # oovr report's plots; oovr paper's and beyond's charts as PDF and PNG
  # beside their SVG (rsvg-convert)
  python3-matplotlib python3-numpy librsvg2-bin
  # the Python module (docs/python.md): pybind11 and Python's headers to
  # build it, pandas for DataFrames, pytest for its tests
  pybind11-dev python3-pybind11 python3-dev python3-pandas python3-pytest
  # libzip's CMake files need its tools installed too
  libzip-dev zipcmp zipmerge ziptool
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # reference renderer: Mesa llvmpipe through EGL surfaceless
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  # test data: models in OBJ, glTF, PLY and AC3D for the loader tests
  assimp-testmodels
)

game_data=(
  openarena-081-maps openarena-081-textures openarena-085-data openarena-088-data openarena-data
  torcs-data
  nexuiz-data
)

services=(
  slurmctld slurmd slurm-client
  chromium fonts-dejavu-core
)

capture=(
  apitrace apitrace-tracers xvfb xauth
  openarena nexuiz
)

for arg in "$@"; do
  case "$arg" in
    --game-data) packages+=("${game_data[@]}") ;;
    --services) packages+=("${services[@]}") ;;
    --capture) packages+=("${capture[@]}") ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "install-deps: unknown option '$arg' (use --game-data, --services, --capture or --help)" >&2; exit 2 ;;
  esac
done

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
