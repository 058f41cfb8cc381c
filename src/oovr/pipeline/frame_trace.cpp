// FrameTrace's totals (frame_trace.h), beside the trace they add up.
#include "oovr/pipeline/frame_trace.h"

#include <algorithm>

namespace oovr {

uint64_t FrameTrace::total_covered() const {
  uint64_t n = 0;
  for (const auto& t : tiles) n += t.covered;
  return n;
}

uint64_t FrameTrace::total_passed() const {
  uint64_t n = 0;
  for (const auto& t : tiles) n += t.passed;
  return n;
}

uint64_t FrameTrace::layer_fetches() const {
  uint64_t n = 0;
  for (const auto& t : tiles) n += uint64_t(t.shaded) * objects[t.object].texture_layers;
  return n;
}

uint64_t FrameTrace::unique_tex_lines() const {
  std::vector<TexLine> lines(tex_lines.begin(), tex_lines.end());
  std::sort(lines.begin(), lines.end());
  return uint64_t(std::unique(lines.begin(), lines.end()) - lines.begin());
}

}  // namespace oovr
