#include "oovr/schemes/composition.h"

#include <bit>

#include "oovr/core/config_sections.h"

namespace oovr {

CompositionSpec CompositionSpec::from_config(const Config& c) {
  CompositionSpec s;
  s.depth = c.get_choice("composition.payload", "colour", {"colour", "colour+depth"}) == "colour+depth";
  s.per_pixel = c.get_choice("composition.granularity", "line", {"line", "pixel"}) == "pixel";
  return s;
}

namespace {

const ConfigSections::Add reg(
    "composition",
    {"what sort-last schemes send to the final frame's owners",
     [](const Config& c) { (void)CompositionSpec::from_config(c); },
     {{"composition.payload", "sort-last schemes send colour (depth-tested in the final frame) or colour and depth"},
      {"composition.granularity", "what is sent: whole framebuffer lines written, or 4 bytes per passed pixel"}}});

}  // namespace

Composer::Composer(FrameSim& sim, CompositionSpec spec, std::function<int(int, int)> owner)
    : m_sim(sim), m_spec(spec), m_owner(std::move(owner)) {
  const FrameTrace& f = sim.frame();
  const SceneLayout& layout = sim.layout();
  for (int ty = 0; ty < f.tiles_y; ++ty)
    for (int tx = 0; tx < f.tiles_x; ++tx)
      for (uint32_t region : {sim.colour(0), sim.depth(0)})
        sim.memory().place(layout.frame_line(region, tx, ty, 0), m_owner(tx, ty));
}

void Composer::target(FrameSim::TileJob& job) const {
  job.fbs.clear();
  job.depth_fbs.clear();
  for (const TileWork* r : job.records) {
    const bool mine = owner(*r) == job.gpm;
    job.fbs.push_back(mine ? 0 : 1 + job.gpm);
    job.depth_fbs.push_back(mine || !m_spec.depth ? 0 : 1 + job.gpm);
  }
}

uint64_t Composer::bytes(const TileWork& r) const {
  const uint64_t payloads = m_spec.depth ? 2 : 1;
  if (m_spec.per_pixel) return uint64_t(r.passed) * 4 * payloads;
  return uint64_t(std::popcount(r.colour_write_mask)) * m_sim.frame().line_bytes * payloads;
}

uint64_t Composer::pixels(const TileWork& r) const {
  if (m_spec.per_pixel) return r.passed;
  return uint64_t(std::popcount(r.colour_write_mask)) * (m_sim.frame().line_bytes / 4);
}

void Composer::send(const FrameSim::TileJob& job, int unit) {
  const int n = m_sim.gpms();
  std::vector<uint64_t> bytes(size_t(n), 0), pixels(size_t(n), 0);
  std::vector<std::vector<const TileWork*>> sent_to(static_cast<size_t>(n));
  for (const TileWork* r : job.records) {
    const int o = owner(*r);
    if (o == job.gpm) continue;
    bytes[size_t(o)] += this->bytes(*r);
    pixels[size_t(o)] += this->pixels(*r);
    sent_to[size_t(o)].push_back(r);
  }
  for (int o = 0; o < n; ++o)
    if (bytes[size_t(o)]) {
      const int sent = m_sim.transfer(job.gpm, o, bytes[size_t(o)], Category::composition, {unit});
      m_sim.compose(o, sent_to[size_t(o)], pixels[size_t(o)], {sent});
    }
}

}  // namespace oovr
