#!/bin/sh
# A short real capture (docs/real-frames.md): scripts/capture-frames.sh
# records OpenArena's demo088 under apitrace up to frame 47 and glretrace
# (apitrace's replayer, on llvmpipe) snapshots frames 40 to 47; then
#  - oovr's mono image of each of those frames must reach 40 dB PSNR
#    against glretrace's (oovr check-capture);
#  - oovr's draws and triangles of each frame must be what `apitrace dump`
#    lists for it (draw calls: glDrawElements, glDrawArrays,
#    glDrawRangeElements, glBegin/glEnd; triangles as OpenGL splits them).
# Exit 77 (skipped) when apitrace, Xvfb or OpenArena's engine is missing
# (scripts/install-deps.sh --capture installs them; CI does).
#
#   capture.sh OOVR WORKDIR SOURCE_DIR
set -eu
oovr=$1
work=$2
src=$3
. "$src/tests/cli/capture_lib.sh"
require_capture_tools /usr/games/openarena
rm -rf "$work"
mkdir -p "$work"
export OOVR_CAPTURE_DIR="$work/captures" OOVR_CACHE_DIR="$work/cache"
OOVR="$oovr" "$src/scripts/capture-frames.sh" openarena --frames 40-47
# Idempotent: a second run does nothing.
OOVR="$oovr" "$src/scripts/capture-frames.sh" openarena --frames 40-47 | grep -q "is there"
"$oovr" scenes | grep -q "^oa-demo:demo088 "

"$oovr" check-capture --scene oa-demo:demo088 --snapshots "$work/captures/openarena-demo088.snapshots" --min-frames 8 \
  >"$work/check.txt"
cat "$work/check.txt"
# Again: the import now comes from the cache of imports (where the build is
# a commit's), and must give the same frames.
"$oovr" check-capture --scene oa-demo:demo088 --snapshots "$work/captures/openarena-demo088.snapshots" --min-frames 8 \
  >"$work/check2.txt"
cmp "$work/check.txt" "$work/check2.txt" || { echo "a second import differs:"; diff "$work/check.txt" "$work/check2.txt"; exit 1; }

# What apitrace itself lists, frame by frame, against check-capture's rows.
counts_match "$work/captures/openarena-demo088.trace" 40 47 "$work/check.txt" 0 0
# The gate bites: no frame reaches 99 dB.
if "$oovr" check-capture --scene oa-demo:demo088 --snapshots "$work/captures/openarena-demo088.snapshots" --min-psnr 99 \
  >/dev/null 2>"$work/gate.txt"; then
  echo "a 99 dB gate passed"
  exit 1
fi
grep -q "oovr: error: 0 of 8 frames reach 99.0 dB" "$work/gate.txt" || { cat "$work/gate.txt"; exit 1; }
# A simulation names the game's frame it measured and its draws.
d40=$(awk '$1 == 40 { print $2 }' "$work/dump.txt")
"$oovr" simulate --scene oa-demo:demo088 --scheme baseline --frames 1 --resolution 640x480 >"$work/simulate.txt"
grep -q "the game's frame 40: draws per frame median $d40 " "$work/simulate.txt" || { cat "$work/simulate.txt"; exit 1; }
echo "capture-ok: 8 frames, draws and triangles as apitrace dump lists them"
