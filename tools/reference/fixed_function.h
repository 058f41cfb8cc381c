// A built-in scene drawn as an OpenGL 1.x game draws (docs/real-frames.md,
// "The round trip"): Mesa's llvmpipe in a compatibility context on a
// pbuffer, the game's camera in the projection and modelview matrices,
// vertices from client arrays, each layer on its own texture unit with its
// texture environment, one eglSwapBuffers a frame. It is what the test
// suite captures with apitrace and imports back (tests/cli/roundtrip.sh):
// nothing here is oovr's own drawing, so the import must rebuild the scene
// from what OpenGL was told.
#pragma once

#include <string>

#include "oovr/pipeline/image.h"
#include "oovr/scene/scene.h"

namespace oovr::reference {

struct FixedFunctionRun {
  int first_frame = 0, frames = 1;
  int width = 640, height = 480;  // the window (one view, mono)
};

// Why `scene` cannot be drawn through OpenGL 1.x's fixed function (layers
// beyond two, per-pixel lighting, a layer scale texture_env_combine cannot
// apply, animated texture coordinates, vertex colours), or "" when it can.
std::string fixed_function_refusal(const Scene& scene);

// Draws the frames; returns the last one's image (bottom row first).
// Throws Unavailable when no compatibility context on a pbuffer can be made,
// Error when the scene is refused.
Image draw_fixed_function(const Scene& scene, const FixedFunctionRun& run);

}  // namespace oovr::reference
