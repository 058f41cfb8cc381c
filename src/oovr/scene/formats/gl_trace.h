// An interpreter of the OpenGL a captured game sent to its GPU (an apitrace
// file, scene/formats/apitrace.h), turning a window of its frames into a
// Scene whose camera path is those frames and whose draws are, frame by
// frame, what the game drew (Scene::frame_objects).
//
// It models fixed-function OpenGL 1.x as ioquake3's `opengl1` renderer
// drives it (docs/real-frames.md lists every call): client arrays with the
// data apitrace records before each draw, glDrawElements/glDrawArrays,
// glLockArraysEXT, immediate mode, the matrix stacks, textures with their
// uploads and parameters, two texture units and their environments,
// blending, alpha test, depth and colour masks, culling, polygon offset,
// scissor, viewport and depth range. Each draw becomes an object with its
// mesh (positions, two sets of coordinates and colours, de-duplicated by
// content across frames), its material (textures and state, de-duplicated)
// and its view: 3-D draws (a perspective projection) are re-projected for
// each eye, 2-D draws (an orthographic one) are drawn alike in both.
// And OpenGL 3 with GLSL as DarkPlaces and ioquake3's `opengl2` drive it:
// buffer objects, vertex array objects, programs and their uniforms, each
// program mapped onto a pass (scene/formats/gl_programs.h).
//
// A call it does not model is either on its list of calls that change
// nothing drawn, or state it refuses to draw with (fog, lighting, stencil,
// lines...), which is an Error naming the call and the frame when a draw
// of the window meets it: never silently skipped.
#pragma once

#include <cstdint>
#include <string>

#include "oovr/scene/scene.h"

namespace oovr {

// The name of the depth-only rectangle a depth clear after a frame's first
// draw becomes (it is not one of the game's draw calls).
constexpr const char* kDepthClearName = "depth clear";
inline bool is_depth_clear(const Object& o) { return o.name == kDepthClearName; }

// A captured frame as the game drew it: its draw calls, their triangles
// (as OpenGL splits them) and how many of them are 2-D, and the depth
// clears oovr draws besides.
struct GameDraws {
  uint64_t draws = 0, triangles = 0, screen = 0, clears = 0;
};
GameDraws game_draws(const Scene& scene, int frame);

struct GlTraceWindow {
  int first = 0;   // first frame (0: the trace's first), counted as apitrace counts them
  int count = 64;  // frames imported
  // Scene units to metres: the game's eye space is scaled by it, so that
  // the stereo rig's interpupillary distance (metres) is right. Quake's
  // units are inches.
  float metres_per_unit = 0.0254f;
};

// Per-window statistics of the import, for `oovr scene-info` and the docs.
struct GlTraceStats {
  uint64_t calls = 0;            // calls read, up to the window's end
  uint64_t frames_in_trace = 0;  // frames read (up to the window's end)
  uint64_t draws = 0;            // draws of the window (glDrawElements, glDrawArrays, glBegin/glEnd)
  uint64_t screen_draws = 0;     // of them 2-D
  uint64_t triangles = 0;
  uint64_t clears = 0;           // depth clears after a frame's first draw (drawn as a depth-only rectangle)
  uint64_t texture_uploads = 0;  // glTexImage2D/glTexSubImage2D, whole trace up to the window's end
};

// Imports frames [first, first + count) of the trace at `path`. Throws
// Error naming the file, frame and call when the trace is malformed, has
// fewer frames, or draws with state oovr does not model.
Scene import_gl_trace(const std::string& path, const GlTraceWindow& window, GlTraceStats* stats = nullptr);
// The same from a trace held in memory (tests, the fuzz target).
Scene import_gl_trace_bytes(std::string bytes, const std::string& name, const GlTraceWindow& window,
                            GlTraceStats* stats = nullptr);

}  // namespace oovr
