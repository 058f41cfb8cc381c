#!/bin/sh
# A short capture of ioquake3's GLSL renderer (docs/real-frames.md, "GLSL
# games"): scripts/capture-frames.sh records OpenArena's demo088 drawn by
# the `opengl2` renderer under apitrace up to frame 47, and glretrace
# snapshots frames 40 to 47; then
#  - oovr's mono image of each frame must reach 40 dB PSNR against
#    glretrace's (the programs' vertex stages are evaluated per vertex and
#    their fragment stages are products of textures: 47 to 52 dB measured
#    over frames 40 to 103, docs/validation.md);
#  - oovr's draws and triangles of each frame must be what `apitrace dump`
#    lists (the depth pre-pass's draws included).
# Exit 77 (skipped) when apitrace, Xvfb or OpenArena's engine is missing
# (scripts/install-deps.sh --capture installs them; CI does).
#
#   capture_gl2.sh OOVR WORKDIR SOURCE_DIR
set -eu
oovr=$1
work=$2
src=$3
. "$src/tests/cli/capture_lib.sh"
require_capture_tools /usr/games/openarena
rm -rf "$work"
mkdir -p "$work"
export OOVR_CAPTURE_DIR="$work/captures" OOVR_CACHE_DIR="$work/cache"
OOVR="$oovr" "$src/scripts/capture-frames.sh" openarena-gl2 --frames 40-47
"$oovr" scenes | grep -q "^oa-demo:demo088-gl2 "
status=0
"$oovr" check-capture --scene oa-demo:demo088-gl2 --snapshots "$work/captures/openarena-demo088-gl2.snapshots" \
  --min-frames 8 >"$work/check.txt" 2>&1 || status=$?
cat "$work/check.txt"
[ "$status" -eq 0 ] || exit 1

# What apitrace lists, frame by frame, against check-capture's rows.
counts_match "$work/captures/openarena-demo088-gl2.trace" 40 47 "$work/check.txt" 0 0
# The programs were read, not refused or approximated: the import says
# nothing of approximated colours.
"$oovr" scene-info --scene oa-demo:demo088-gl2 >"$work/info.txt"
if grep -q "approximat" "$work/info.txt"; then
  cat "$work/info.txt"
  echo "the import approximated colours"
  exit 1
fi
echo "capture-gl2-ok: 8 frames, draws and triangles as apitrace dump lists them"
