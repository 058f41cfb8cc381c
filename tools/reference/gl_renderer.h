// The reference renderer: draws a scene through a real OpenGL implementation
// (Mesa's llvmpipe, headless through EGL's surfaceless platform) with the
// same geometry, textures (every mip level uploaded as oovr built it),
// sampler settings, cameras and draw order as oovr's pipeline, and counts the
// fragments of every draw with GL_SAMPLES_PASSED queries.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "oovr/pipeline/image.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr::reference {

// Thrown when no OpenGL 4.5 context can be made (no EGL, no llvmpipe).
class Unavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DrawCounts {
  uint64_t covered = 0;  // fragments rasterised (depth test always passes, no discard)
  uint64_t passed = 0;   // fragments that passed alpha and depth tests in the real render
};

struct GlFrame {
  Image colour;  // bottom row first, as glReadPixels returns it
  // counts[object * 2 + eye]
  std::vector<DrawCounts> counts;
  // Wall-clock time of an image pass without queries (draws to
  // glReadPixels), not counting texture and buffer uploads or the counting
  // passes.
  double render_ms = 0;
};

class GlRenderer {
 public:
  GlRenderer();  // throws Unavailable
  ~GlRenderer();
  GlRenderer(const GlRenderer&) = delete;
  GlRenderer& operator=(const GlRenderer&) = delete;

  std::string renderer_name() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  GlFrame render(const Scene& scene, const StereoView& view);

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

}  // namespace oovr::reference
