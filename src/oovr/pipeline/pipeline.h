// The functional stereo pipeline (DESIGN.md, "Data flow"):
//
//   vertex transform (once per object) -> SMP projection into both eyes ->
//   clip (near/far, guard band) and back-face cull -> 16x16 tile binning ->
//   fixed-point rasterisation -> texture sampling -> alpha and depth test ->
//   colour write
//
// It produces the stereo image and the FrameTrace that schemes replay. It
// knows nothing of GPMs or time.
#pragma once

#include <cstdint>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/pipeline/frame_trace.h"
#include "oovr/pipeline/image.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr {

struct PipelineSettings {
  // Maximum anisotropic filtering taps (1 = isotropic trilinear, as the
  // reference comparison uses; 16 = the paper's Table 1).
  int max_anisotropy = 16;
  // Cache line size used for texture and framebuffer line addresses in the
  // trace: a power of two from 32 to 1024 bytes.
  uint32_t line_bytes = 128;
  // Worker threads for rasterisation (0 = automatic). Results do not depend
  // on it.
  unsigned threads = 0;
  // Record texture lines in the trace (the largest part of it).
  bool record_texture_lines = true;
  // Draw the image and object ids. Without them, render_frame gives the
  // trace alone, the same bit for bit, in less time: passes whose fragments
  // cannot be discarded record their texture lines and lookups without
  // fetching or filtering a texel, and nothing is blended or written but
  // depth (raster.h). `simulate`, `compare` and sweeps render so every
  // frame whose picture they do not use.
  bool draw_image = true;
  // How textures are stored in memory (footprint and traffic; the image is
  // the same). The games oovr's workloads stand for shipped or uploaded
  // their textures block-compressed (docs/model.md), so the default is the
  // games' rule: BC1 for opaque images, BC3 for images with alpha,
  // lightmaps uncompressed.
  TextureFormat texture_format = TextureFormat::bc;

  // Throws Error naming the bad setting.
  void validate() const;
  // The settings a configuration names (key pipeline.texture_format); the
  // rest keep their defaults.
  static PipelineSettings from_config(const Config& c);
};

constexpr int kTileSize = 16;
constexpr uint32_t kNoObject = 0xffffffffu;

struct FrameOutput {
  // Both empty when drawn without the image (PipelineSettings::draw_image).
  Image colour;                             // frame_width x frame_height, bottom row first; cleared to opaque black
  UninitialisedVector<uint32_t> object_id;  // per pixel: object that last wrote it, or kNoObject
  FrameTrace trace;
};

// Renders frame `frame` of the scene's camera path through `view`.
FrameOutput render_frame(const Scene& scene, const StereoView& view, const PipelineSettings& settings, int frame = 0);

}  // namespace oovr
