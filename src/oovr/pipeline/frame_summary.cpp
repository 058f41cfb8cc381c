#include "oovr/pipeline/frame_summary.h"

#include <algorithm>

namespace oovr {

FrameSummary summarise(const FrameOutput& out) {
  const FrameTrace& tr = out.trace;
  FrameSummary s;
  s.frame = tr.frame;
  s.frame_width = tr.frame_width;
  s.frame_height = tr.frame_height;
  s.draws = tr.objects.size();
  for (const auto& o : tr.objects) {
    s.setup[0] += o.setup[0];
    s.setup[1] += o.setup[1];
    s.culled += o.culled[0] + o.culled[1];
  }
  for (const auto& t : tr.tiles) {
    s.quads += t.quads;
    s.shaded += t.shaded;
  }
  s.covered = tr.total_covered();
  s.passed = tr.total_passed();
  s.records = tr.tiles.size();
  s.texture_line_reads = tr.tex_lines.size();
  s.line_bytes = tr.line_bytes;
  s.pixels_drawn =
      uint64_t(std::count_if(out.object_id.begin(), out.object_id.end(), [](uint32_t id) { return id != kNoObject; }));
  s.layer_fetches = tr.layer_fetches();
  s.texture_bytes_touched = tr.unique_tex_lines() * tr.line_bytes;
  return s;
}

}  // namespace oovr
