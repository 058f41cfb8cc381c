#!/bin/sh
# A short capture of a GLSL game (docs/real-frames.md, "GLSL games"):
# scripts/capture-frames.sh records Nexuiz's benchmark demo bench1, drawn
# by DarkPlaces' OpenGL 3.2 renderer, under apitrace up to frame 107, and
# glretrace snapshots frames 100 to 107; then
#  - oovr's mono image of each frame must reach 30 dB PSNR against
#    glretrace's (the programs' colours are approximated where oovr's
#    passes cannot compute them; 30 to 36 dB measured over frames 100 to
#    163, docs/validation.md);
#  - oovr's draws and triangles of each frame must be what `apitrace dump`
#    lists, less the one draw a frame that copies the view into the window.
# Exit 77 (skipped) when apitrace, Xvfb, Nexuiz's engine or its data is
# missing (scripts/install-deps.sh --capture --game-data installs them).
#
#   capture_nexuiz.sh OOVR WORKDIR SOURCE_DIR
set -eu
oovr=$1
work=$2
src=$3
. "$src/tests/cli/capture_lib.sh"
require_capture_tools /usr/games/nexuiz
if [ ! -f /usr/share/games/nexuiz/data/data.pk3 ]; then
  echo "skipped: Nexuiz's data is not installed (scripts/install-deps.sh --game-data)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
export OOVR_CAPTURE_DIR="$work/captures" OOVR_CACHE_DIR="$work/cache"
OOVR="$oovr" "$src/scripts/capture-frames.sh" nexuiz --frames 100-107
"$oovr" scenes | grep -q "^nexuiz-demo:bench1 "
status=0
"$oovr" check-capture --scene nexuiz-demo:bench1 --snapshots "$work/captures/nexuiz-bench1.snapshots" --min-psnr 30 \
  --min-frames 8 >"$work/check.txt" 2>&1 || status=$?
cat "$work/check.txt"
[ "$status" -eq 0 ] || exit 1

# What apitrace lists, frame by frame, against check-capture's rows with
# the copy of the view into the window (the last draw of each frame, 2
# triangles) added back.
counts_match "$work/captures/nexuiz-bench1.trace" 100 107 "$work/check.txt" 1 2
# The import says what it stood in for: one copy of the view a frame.
"$oovr" scene-info --scene nexuiz-demo:bench1 >"$work/info.txt"
grep -q "8 draws copied the view, rendered into a texture, into the window" "$work/info.txt" ||
  { cat "$work/info.txt"; echo "the copies of the view are not counted"; exit 1; }
echo "capture-nexuiz-ok: 8 frames, draws and triangles as apitrace dump lists them"
