#!/usr/bin/env bash
# Captures what a real game sends to its GPU, for oovr's captured-frame
# scenes (docs/real-frames.md): the game plays a demo it ships, headless
# (Xvfb, Mesa's llvmpipe), under apitrace; the capture is cut after the
# window of frames oovr imports and kept in oovr's capture folder, where
# `oovr scenes` lists it.
#
# Usage: scripts/capture-frames.sh GAME [--frames A-B] [--force]
#   GAME      openarena: OpenArena 0.8.8's demo088-test1 (map oa_shouse,
#             bots), drawn by ioquake3's fixed-function `opengl1` renderer;
#             scene oa-demo:demo088
#             openarena-gl2: the same demo drawn by ioquake3's GLSL `opengl2`
#             renderer (OpenArena's default) with the settings oovr models
#             (docs/real-frames.md); scene oa-demo:demo088-gl2
#             nexuiz: Nexuiz 2.5.2's benchmark demo bench1, drawn by
#             DarkPlaces' GLSL renderer with the settings oovr models
#             (docs/real-frames.md); scene nexuiz-demo:bench1
#   --frames  the window oovr imports by default (default 40-103 for
#             openarena and openarena-gl2, 100-163 for nexuiz: the loading
#             screens first)
#   --force   capture again even when the capture is there
#
# Idempotent: installs what is missing (scripts/install-deps.sh --capture),
# does nothing when the capture exists with the same window. The folder is
# $OOVR_CAPTURE_DIR, else $XDG_CACHE_HOME/oovr/captures, else
# ~/.cache/oovr/captures; beside the capture, glretrace's snapshots of the
# window's frames (NAME.snapshots/, for `oovr check-capture`). Takes about
# half a minute on 2 cores; the kept file is 60 to 110 MB.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,25p' "$0"; }
game="" frames="" force=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --frames) [[ $# -ge 2 ]] || { echo "capture-frames: --frames needs A-B" >&2; exit 2; }; frames="$2"; shift 2 ;;
    --force) force=1; shift ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "capture-frames: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) [[ -z "$game" ]] || { echo "capture-frames: one game at a time" >&2; exit 2; }; game="$1"; shift ;;
  esac
done
case "$game" in
  openarena|openarena-gl2) : "${frames:=40-103}" ;;
  nexuiz) : "${frames:=100-163}" ;;
esac
if [[ ! "$frames" =~ ^([0-9]{1,7})-([0-9]{1,7})$ ]]; then
  echo "capture-frames: --frames must be A-B, the first and last frame, not '$frames'" >&2
  exit 2
fi
# Base 10 whatever the leading zeros ("08" is not octal here).
first=$((10#${BASH_REMATCH[1]}))
last=$((10#${BASH_REMATCH[2]}))
if (( last < first )); then
  echo "capture-frames: --frames must be A-B with A <= B, not '$frames'" >&2
  exit 2
fi
frames="$first-$last"

# Each capture is kept as PREFIX-NAME.trace: the scene PREFIX's source
# (oa-demo for openarena, nexuiz-demo for nexuiz) reads NAME from there.
case "$game" in
  openarena)
    prefix=openarena name=demo088 scene=oa-demo:demo088
    command=(/usr/games/openarena +set cl_renderer opengl1 +set s_initsound 0 +set timedemo 1
             +set nextdemo quit +demo demo088-test1)
    ;;
  openarena-gl2)
    prefix=openarena name=demo088-gl2 scene=oa-demo:demo088-gl2
    # ioquake3's opengl2 renderer as oovr's interpreter reads it
    # (docs/real-frames.md): straight into the window (no HDR, no
    # multisampling: no render target, tone map or auto-exposure), lit by
    # its fast path (no normal, specular, deluxe or cube maps), no sun
    # shadows, screen-space ambient occlusion or projected shadows; the
    # demo, the depth pre-pass and the dynamic lights as the game draws them.
    # The bigger hunk is what the renderer needs to load the map.
    command=(/usr/games/openarena +set cl_renderer opengl2 +set com_hunkmegs 256 +set s_initsound 0 +set timedemo 1
             +set nextdemo quit +set r_hdr 0 +set r_ext_framebuffer_multisample 0 +set r_postProcess 0
             +set r_normalMapping 0 +set r_specularMapping 0 +set r_deluxeMapping 0 +set r_cubeMapping 0
             +set r_sunlightMode 0 +set r_ssao 0 +set r_dlightMode 0 +set r_pshadowDist 0 +demo demo088-test1)
    ;;
  nexuiz)
    prefix=nexuiz name=bench1 scene=nexuiz-demo:bench1
    # DarkPlaces' OpenGL 3.2 renderer as oovr's interpreter reads it
    # (docs/real-frames.md): no post-processing, water, skeletal animation
    # on the GPU, real-time dynamic lights, deluxe or offset mapping, model
    # shadows; gamma 1 (the view composited unchanged); uncompressed textures.
    command=(/usr/games/nexuiz -benchmark demos/bench1 -nosound +vid_fullscreen 0 +vid_width 640 +vid_height 480
             +r_glsl_skeletal 0 +r_bloom 0 +r_hdr 0 +r_water 0 +r_glsl_postprocess 0 +r_motionblur 0 +r_damageblur 0
             +r_coronas 0 +r_shadow_realtime_dlight 0 +r_shadows 0 +r_glsl_deluxemapping 0 +r_glsl_offsetmapping 0
             +gl_texturecompression 0 +v_gamma 1 +v_contrast 1 +v_brightness 0 +vid_sRGB 0)
    ;;
  "") usage >&2; exit 2 ;;
  *) echo "capture-frames: unknown game '$game' (games: openarena, openarena-gl2, nexuiz)" >&2; exit 2 ;;
esac

dir=${OOVR_CAPTURE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/oovr/captures}
trace="$dir/$prefix-$name.trace"
window="$dir/$prefix-$name.frames"
snapshots="$dir/$prefix-$name.snapshots"
if [[ $force -eq 0 && -f "$trace" && -f "$window" && -d "$snapshots" && "$(cat "$window")" == "$frames" ]]; then
  echo "capture-frames: $trace is there (frames $frames); --force captures again"
  exit 0
fi

scripts/install-deps.sh --capture
oovr=${OOVR:-build/release/oovr}
if [[ ! -x "$oovr" ]]; then
  echo "capture-frames: building oovr first (make build)"
  make build >/dev/null
fi

mkdir -p "$dir"
work=$(mktemp -d "$dir/.capture-XXXXXX")
trap 'rm -rf "$work"' EXIT
# The game's settings and logs stay in the scratch folder, not in ~/.openarena
# or ~/.nexuiz.
export HOME="$work/home"
mkdir -p "$HOME"
echo "capture-frames: recording ${command[*]} under apitrace until frame $last"
# The demo runs for 3,398 frames (1.9 GB of trace); the game is stopped once
# the trace surely holds the window (about 0.6 MB a frame here, 2 MB allowed),
# and the capture is cut after the window's last frame at a chunk boundary.
limit=$(( (last + 1) * 2 * 1024 * 1024 + 32 * 1024 * 1024 ))
setsid xvfb-run -a -s "-screen 0 640x480x24" apitrace trace -o "$work/full.trace" "${command[@]}" >"$work/game.log" 2>&1 &
game_pid=$!
while kill -0 "$game_pid" 2>/dev/null; do
  size=$(stat -c %s "$work/full.trace" 2>/dev/null || echo 0)
  if (( size >= limit )); then
    kill -TERM -- "-$game_pid" 2>/dev/null || true
    break
  fi
  sleep 0.5
done
wait "$game_pid" 2>/dev/null || true
# The game may outlive its X server: ioquake3's opengl2 renderer once hung
# here in its shutdown after the signal, holding 600 MB. Whatever is left of
# its process group after 10 s is killed.
for _ in $(seq 20); do
  kill -0 -- "-$game_pid" 2>/dev/null || break
  sleep 0.5
done
kill -KILL -- "-$game_pid" 2>/dev/null || true
if [[ ! -s "$work/full.trace" ]]; then
  tail -20 "$work/game.log" >&2
  echo "capture-frames: the game wrote no trace under apitrace (its log is above)" >&2
  exit 1
fi
"$oovr" trace-cut --in "$work/full.trace" --out "$work/cut.trace" --last-frame "$last"

# The real driver's image of every frame of the window: glretrace replays
# the kept capture on llvmpipe (oovr check-capture compares with them).
mkdir -p "$work/snapshots"
if ! xvfb-run -a -s "-screen 0 640x480x24" glretrace -s "$work/snapshots/" --call-nos=false "$work/cut.trace" \
     >"$work/retrace.log" 2>&1; then
  tail -20 "$work/retrace.log" >&2
  echo "capture-frames: glretrace could not replay the capture (its log is above)" >&2
  exit 1
fi
for f in "$work/snapshots"/*.png; do
  n=$(basename "$f" .png)
  (( 10#$n >= first && 10#$n <= last )) || rm -f "$f"
done

rm -rf "$snapshots"
mv "$work/snapshots" "$snapshots"
mv "$work/cut.trace" "$trace"
printf '%s\n' "$frames" >"$window"
echo "capture-frames: kept frames 0 to $last in $trace ($(du -h "$trace" | cut -f1)), glretrace's snapshots of" \
     "frames $frames in $snapshots; scene $scene"
