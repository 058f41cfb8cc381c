#!/bin/sh
# The round trip (docs/validation.md): oovr-reference draws frames 0 to 3
# of the built-in courtyard through OpenGL 1.x (--fixed-function: client
# arrays, texture environments, the camera in the projection and modelview
# matrices) while apitrace captures it; the capture, imported by oovr's
# reader and interpreter, must draw what the scene draws:
#  - the same draws and triangles in every frame, covered and passed
#    fragments within 0.01% and images of at least 80 dB
#    (oovr check-capture --against courtyard);
#  - llvmpipe's own image of the last frame against oovr's (40 dB, as
#    glretrace's snapshots of a game): OpenGL's fixed function computes
#    what oovr's passes define.
# The gates bite: the capture against another scene, and a capture that
# starts a frame later, must fail.
# Exit 77 (skipped) when apitrace or its EGL tracer is missing
# (scripts/install-deps.sh --capture installs them) or no OpenGL
# compatibility context can be made.
#
#   roundtrip.sh OOVR OOVR_REFERENCE WORKDIR
set -eu
oovr=$1
ref=$2
work=$3
if ! command -v apitrace >/dev/null 2>&1; then
  echo "skipped: apitrace is not installed (scripts/install-deps.sh --capture)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work/snapshots"
# Under the sanitizers (make asan): Mesa's driver, which oovr-reference
# loads, keeps allocations until exit; its leaks are not oovr's (as for the
# reference.* tests). oovr itself is still checked for leaks.
ref_env="ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
export OOVR_CACHE_DIR="$work/cache"
status=0
env "$ref_env" "$ref" --fixed-function --scene courtyard --frames 4 --resolution 320x240 --out "$work/direct.png" \
  >"$work/direct.txt" || status=$?
cat "$work/direct.txt"
[ "$status" -ne 77 ] || exit 77
[ "$status" -eq 0 ] || { echo "oovr-reference --fixed-function failed ($status)"; exit 1; }
capture() {
  # $1: the file, then the reference's arguments.
  out=$1
  shift
  if ! env "$ref_env" apitrace trace --api egl -o "$out" "$ref" --fixed-function --scene courtyard --resolution 320x240 "$@" \
    >"$work/trace.txt" 2>&1; then
    cat "$work/trace.txt"
    if grep -q "egltrace" "$work/trace.txt"; then
      echo "skipped: apitrace cannot trace EGL here"
      exit 77
    fi
    echo "apitrace trace failed"
    exit 1
  fi
}
capture "$work/rt.trace" --frames 4
# (Not piped: a pipeline's status is its last command's.)
status=0
"$oovr" check-capture --scene "trace:$work/rt.trace?frames=0-3" --against courtyard --min-psnr 80 >"$work/check.txt" 2>&1 ||
  status=$?
cat "$work/check.txt"
[ "$status" -eq 0 ] || exit 1
# llvmpipe's image of frame 3 as a snapshot of the capture.
cp "$work/direct.png" "$work/snapshots/0000000003.png"
"$oovr" check-capture --scene "trace:$work/rt.trace?frames=0-3" --snapshots "$work/snapshots" --min-frames 1 \
  >"$work/gl.txt" 2>&1 || status=$?
cat "$work/gl.txt"
[ "$status" -eq 0 ] || exit 1

# Against another scene: other draws.
if "$oovr" check-capture --scene "trace:$work/rt.trace?frames=0-3" --against crowd >/dev/null 2>"$work/gate.txt"; then
  echo "the capture of courtyard passed against crowd"
  exit 1
fi
grep -q "oovr: error: the capture differs from crowd: frame 0 has other draws or triangles" "$work/gate.txt" ||
  { cat "$work/gate.txt"; exit 1; }
# A capture of frames 1 to 4 taken for frames 0 to 3: the same draws, other images.
capture "$work/late.trace" --frame 1 --frames 4
if "$oovr" check-capture --scene "trace:$work/late.trace?frames=0-3" --against courtyard --min-psnr 80 \
  >/dev/null 2>"$work/gate.txt"; then
  echo "a capture a frame late passed"
  exit 1
fi
grep -q "oovr: error: the capture differs from courtyard: frame 0 reaches [0-9.]* dB, under 80.0" "$work/gate.txt" ||
  { cat "$work/gate.txt"; exit 1; }
echo "roundtrip-ok"
