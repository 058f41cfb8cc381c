// The reference renderer: draws a scene through a real OpenGL implementation
// with the same geometry, textures (every mip level uploaded as oovr built
// it), sampler settings, cameras and draw order as oovr's pipeline. For the
// image comparison it is Mesa's llvmpipe, headless through EGL's surfaceless
// platform, and counts the fragments of every draw with GL_SAMPLES_PASSED
// queries. For timing it is whatever OpenGL the machine has: a GPU through
// EGL's device platform (EGL_EXT_platform_device, how NVIDIA's driver runs
// headless), else llvmpipe; frames are timed on the GPU with
// GL_TIME_ELAPSED queries.
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

// GPU time of one stereo frame, in microseconds (docs/validation.md,
// "Hardware"): medians over the repetitions.
struct FrameTime {
  double full_us = 0;  // every draw, both eyes
  double geom_us = 0;  // the same with a 1x1 scissor per eye: per-draw and vertex cost, almost no fragments
  double left_us = 0;  // the left eye only
};

enum class Platform {
  llvmpipe,  // Mesa's llvmpipe on the surfaceless platform (the image comparison)
  any,       // the first hardware EGL device, else llvmpipe (timing)
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
  explicit GlRenderer(Platform platform = Platform::llvmpipe);  // throws Unavailable
  ~GlRenderer();
  GlRenderer(const GlRenderer&) = delete;
  GlRenderer& operator=(const GlRenderer&) = delete;

  std::string renderer_name() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  GlFrame render(const Scene& scene, int frame, const StereoView& view);
  // Times each view of `views` (`repeats` times after one warm-up, medians)
  // with anisotropic filtering up to `aniso` taps; framebuffer cleared
  // before every timed pass, outside the timer.
  std::vector<FrameTime> time(const Scene& scene, const std::vector<int>& frames, const std::vector<StereoView>& views, int aniso,
                              int repeats);

  // Wall-clock seconds to draw each of `views` in turn as a whole frame:
  // clear, every draw of both eyes with filtering up to `aniso` taps, and
  // glReadPixels (a frame is done when its pixels are back, as oovr's is
  // when its image is written). Textures and buffers are uploaded before
  // the clock starts. What bench/speed.cpp sets oovr's times beside.
  double draw_seconds(const Scene& scene, const std::vector<int>& frames, const std::vector<StereoView>& views, int aniso);

  struct Impl;  // the EGL context, program and uniforms (gl_renderer.cpp)

 private:
  std::unique_ptr<Impl> m;
};

}  // namespace oovr::reference
