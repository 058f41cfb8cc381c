// What one rendered frame amounts to: the figures `oovr render` prints and
// the Python module's render() returns, counted once from the FrameOutput.
#pragma once

#include <cstdint>

#include "oovr/pipeline/pipeline.h"

namespace oovr {

struct FrameSummary {
  int frame = 0;
  int frame_width = 0, frame_height = 0;
  uint64_t draws = 0;               // objects in the trace
  uint64_t setup[2] = {0, 0};       // triangles set up per eye (after clip and cull)
  uint64_t culled = 0;              // triangles dropped, both eyes: back-facing, empty or outside the view
  uint64_t covered = 0;             // fragments inside triangles
  uint64_t shaded = 0;              // fragments shaded
  uint64_t passed = 0;              // fragments that passed the alpha and depth tests
  uint64_t quads = 0;               // 2x2 quads shaded
  uint64_t records = 0;             // (object, eye, tile) records
  uint64_t texture_line_reads = 0;  // texture lines read, in shading order
  uint32_t line_bytes = 0;
  uint64_t pixels_drawn = 0;   // pixels some draw wrote (0 when the output has no object ids)
  uint64_t layer_fetches = 0;  // texture layers sampled, over the shaded fragments
  uint64_t texture_bytes_touched = 0;

  double layers_per_shaded() const { return shaded ? double(layer_fetches) / double(shaded) : 0.0; }
  double layers_per_pixel() const { return pixels_drawn ? double(layer_fetches) / double(pixels_drawn) : 0.0; }
};

FrameSummary summarise(const FrameOutput& out);

}  // namespace oovr
