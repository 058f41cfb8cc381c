#include "oovr/schemes/composition.h"

#include <algorithm>
#include <bit>
#include <utility>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/schemes/machine_spec.h"
#include "oovr/schemes/sort_first.h"

namespace oovr {

namespace {

struct AlgorithmName {
  CompositionAlgorithm algorithm;
  const char* name;
};
constexpr AlgorithmName kAlgorithms[] = {{CompositionAlgorithm::scheme, "scheme"},
                                         {CompositionAlgorithm::gather, "gather"},
                                         {CompositionAlgorithm::direct_send, "direct-send"},
                                         {CompositionAlgorithm::binary_swap, "binary-swap"},
                                         {CompositionAlgorithm::pairwise, "pairwise"}};

}  // namespace

const char* composition_algorithm_name(CompositionAlgorithm a) {
  for (const AlgorithmName& n : kAlgorithms)
    if (n.algorithm == a) return n.name;
  return "?";
}

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

// The algorithm is a setting of the schemes that take one (their
// registrations name the section): a run of any other scheme neither reads
// nor hashes it, and a sweep refuses it for them.
const ConfigSections::Add sort_last(
    "sort_last", {"how a sort-last scheme's sub-images reach the final frame",
                  nullptr,
                  {{"sort_last.composition",
                    "the scheme's own (object, oo-app: gather; oo-vr: direct-send; chopin: pairwise), gather (to GPM 0), "
                    "direct-send (to vertical strips' owners), binary-swap or pairwise (CHOPIN's N-1 rounds), the last two "
                    "once the GPMs have rendered"}},
                  true,
                  [](const Config& c) {
                    std::vector<std::string> names;
                    for (const AlgorithmName& n : kAlgorithms) names.push_back(n.name);
                    const std::string a = c.get_choice("sort_last.composition", "scheme", names);
                    for (const AlgorithmName& n : kAlgorithms)
                      if (a == n.name) return std::any(n.algorithm);
                    return std::any(CompositionAlgorithm::scheme);
                  }});

void bisect(std::vector<int>& out, int tiles_x, int x0, int x1, int y0, int y1, int first, int parts) {
  if (parts == 1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) out[size_t(y) * size_t(tiles_x) + size_t(x)] = first;
    return;
  }
  const int a = parts / 2, b = parts - a;
  if (x1 - x0 >= y1 - y0) {
    const int cut = x0 + int((int64_t(x1 - x0) * a) / parts);
    bisect(out, tiles_x, x0, cut, y0, y1, first, a);
    bisect(out, tiles_x, cut, x1, y0, y1, first + a, b);
  } else {
    const int cut = y0 + int((int64_t(y1 - y0) * a) / parts);
    bisect(out, tiles_x, x0, x1, y0, cut, first, a);
    bisect(out, tiles_x, x0, x1, cut, y1, first + a, b);
  }
}

// The largest power of two not above n (n >= 1).
int power_of_two_below(int n) { return int(std::bit_floor(unsigned(n))); }

}  // namespace

std::vector<int> bisected_owners(int tiles_x, int tiles_y, int parts) {
  std::vector<int> out(size_t(tiles_x) * size_t(tiles_y), 0);
  if (parts >= 1) bisect(out, tiles_x, 0, tiles_x, 0, tiles_y, 0, parts);
  return out;
}

Composer::Composer(FrameSim& sim, CompositionSpec spec, std::function<int(int, int)> owner)
    : m_sim(sim), m_spec(spec), m_algorithm(CompositionAlgorithm::scheme), m_owner(std::move(owner)) {
  place_final_frame();
}

Composer::Composer(FrameSim& sim, CompositionSpec spec, CompositionAlgorithm fallback)
    : m_sim(sim), m_spec(spec), m_algorithm(sim.spec().own<CompositionAlgorithm>("sort_last")), m_held(size_t(sim.gpms())) {
  if (m_algorithm == CompositionAlgorithm::scheme) m_algorithm = fallback;
  const FrameTrace& f = sim.frame();
  const int n = sim.gpms(), tiles_x = f.tiles_x;
  switch (m_algorithm) {
    case CompositionAlgorithm::scheme:
      throw Error(
          "Composer: a scheme's fallback composition algorithm must be one of gather, direct-send, binary-swap, pairwise");
    case CompositionAlgorithm::gather: m_owner = [](int, int) { return 0; }; break;
    case CompositionAlgorithm::direct_send:
      m_owner = [tiles_x, n](int tx, int) { return vertical_strip_owner(tx, tiles_x, n); };
      break;
    case CompositionAlgorithm::binary_swap:
    case CompositionAlgorithm::pairwise: {
      const int parts = m_algorithm == CompositionAlgorithm::binary_swap ? power_of_two_below(n) : n;
      std::vector<int> owners = bisected_owners(tiles_x, f.tiles_y, parts);
      m_owner = [owners = std::move(owners), tiles_x](int tx, int ty) {
        return owners[size_t(ty) * size_t(tiles_x) + size_t(tx)];
      };
      break;
    }
  }
  place_final_frame();
}

// The final frame's colour and depth pages are homed at their owners (the
// first tile of a page decides), as the paper maps the framebuffer: into
// the root's DRAM (Section 5.3, "the entire FB is mapped in the DRAM of the
// master node"), or with DHC as tile SFR-V maps it.
void Composer::place_final_frame() {
  const FrameTrace& f = m_sim.frame();
  const SceneLayout& layout = m_sim.layout();
  for (int ty = 0; ty < f.tiles_y; ++ty)
    for (int tx = 0; tx < f.tiles_x; ++tx)
      for (uint32_t region : {m_sim.colour(0), m_sim.depth(0)})
        m_sim.place(layout.frame_line(region, tx, ty, 0), m_owner(tx, ty));
}

bool Composer::deferred() const {
  return m_algorithm == CompositionAlgorithm::binary_swap || m_algorithm == CompositionAlgorithm::pairwise;
}

void Composer::target(FrameSim::TileJob& job) const {
  job.fbs.clear();
  job.depth_fbs.clear();
  job.fbs.reserve(job.records.size());
  job.depth_fbs.reserve(job.records.size());
  for (const TileWork* r : job.records) {
    const bool mine = owner(*r) == job.gpm;
    job.fbs.push_back(mine ? 0 : 1 + job.gpm);
    job.depth_fbs.push_back(mine || !m_spec.depth ? 0 : 1 + job.gpm);
  }
}

uint64_t Composer::pixels(uint32_t lines, uint64_t passed) const {
  if (m_spec.per_pixel) return passed;
  return uint64_t(std::popcount(lines)) * (m_sim.frame().line_bytes / 4);
}

// 4 bytes a pixel, twice with depth.
uint64_t Composer::bytes(uint32_t lines, uint64_t passed) const { return pixels(lines, passed) * 4 * (m_spec.depth ? 2 : 1); }

uint64_t Composer::bytes(const TileWork& r) const { return bytes(r.colour_write_mask, r.passed); }
uint64_t Composer::pixels(const TileWork& r) const { return pixels(r.colour_write_mask, r.passed); }

void Composer::Held::add(uint32_t more_lines, uint64_t more_passed, std::span<const TileWork* const> more, uint64_t tile_pixels) {
  lines |= more_lines;
  passed = std::min(tile_pixels, passed + more_passed);
  records.insert(records.end(), more.begin(), more.end());
}

int Composer::owner_of_tile(uint32_t tile) const {
  const uint32_t tiles_x = uint32_t(m_sim.frame().tiles_x);
  return m_owner(int(tile % tiles_x), int(tile / tiles_x));
}

uint64_t Composer::tile_pixels() const { return uint64_t(m_sim.frame().tile_size) * uint64_t(m_sim.frame().tile_size); }

void Composer::send(const FrameSim::TileJob& job, int unit) {
  const int n = m_sim.gpms();
  if (deferred()) {
    const uint32_t tiles_x = uint32_t(m_sim.frame().tiles_x);
    HeldTiles& held = m_held[size_t(job.gpm)];
    for (const TileWork* r : job.records)
      if (owner(*r) != job.gpm)
        held[uint32_t(r->tile_y) * tiles_x + uint32_t(r->tile_x)].add(r->colour_write_mask, r->passed, {&r, 1}, tile_pixels());
    return;
  }
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
      m_units.push_back(sent);
      m_units.push_back(m_sim.compose(o, sent_to[size_t(o)], pixels[size_t(o)], {sent}));
    }
}

std::pair<int, int> Composer::move(int from, int to, HeldTiles tiles, std::vector<int> after, std::vector<int> merge_after) {
  uint64_t bytes = 0, pixels = 0;
  std::vector<const TileWork*> composed;
  HeldTiles& dest = m_held[size_t(to)];
  for (auto& [tile, h] : tiles) {
    bytes += this->bytes(h.lines, h.passed);
    pixels += this->pixels(h.lines, h.passed);
    if (owner_of_tile(tile) == to) composed.insert(composed.end(), h.records.begin(), h.records.end());
    else dest[tile].add(h.lines, h.passed, h.records, tile_pixels());
  }
  if (tiles.empty()) return {-1, -1};
  // A record with nothing written (no line, no fragment passed) sends no
  // byte but still reaches the final frame, through the merge's ledger.
  const int sent = bytes ? m_sim.transfer(from, to, bytes, Category::composition, std::move(after)) : -1;
  if (sent >= 0) m_units.push_back(sent);
  merge_after.push_back(sent);
  merge_after.erase(std::remove(merge_after.begin(), merge_after.end(), -1), merge_after.end());
  const int merged = m_sim.compose(to, composed, pixels, std::move(merge_after));
  m_units.push_back(merged);
  return {sent, merged};
}

Composer::HeldTiles Composer::take(int gpm, const std::function<bool(int owner)>& pick) {
  HeldTiles out;
  HeldTiles& held = m_held[size_t(gpm)];
  for (auto it = held.begin(); it != held.end();)
    if (pick(owner_of_tile(it->first))) {
      out.insert(std::move(*it));
      it = held.erase(it);
    } else {
      ++it;
    }
  return out;
}

void Composer::binary_swap(const std::vector<int>& ready_in) {
  const int n = m_sim.gpms(), p = power_of_two_below(n);
  std::vector<int> ready = ready_in;
  // The fold: GPMs p .. n-1 own no region and hand everything to g - p.
  for (int g = p; g < n; ++g) {
    const int merged = move(g, g - p, std::exchange(m_held[size_t(g)], {}), {ready[size_t(g)]}, {ready[size_t(g - p)]}).second;
    if (merged >= 0) ready[size_t(g - p)] = merged;
  }
  for (int bit = p / 2; bit >= 1; bit /= 2) {
    // Simultaneous exchange: every GPM's packet is taken before any lands.
    std::vector<HeldTiles> out(static_cast<size_t>(p));
    for (int g = 0; g < p; ++g) out[size_t(g)] = take(g, [&](int o) { return ((o ^ g) & bit) != 0; });
    std::vector<int> next = ready;
    for (int g = 0; g < p; ++g) {
      const int partner = g ^ bit;
      const int merged = move(g, partner, std::move(out[size_t(g)]), {ready[size_t(g)]}, {ready[size_t(partner)]}).second;
      if (merged >= 0) next[size_t(partner)] = merged;
    }
    ready = std::move(next);
  }
}

void Composer::pairwise(const std::vector<int>& ready) {
  const int n = m_sim.gpms();
  std::vector<int> last_send(size_t(n), -1), last_receive(size_t(n), -1);
  for (int k = 1; k < n; ++k)
    for (int g = 0; g < n; ++g) {
      const int to = (g + k) % n;
      const int sent = move(g, to, take(g, [to](int o) { return o == to; }),
                            {ready[size_t(g)], last_send[size_t(g)], last_receive[size_t(to)]}, {})
                           .first;
      if (sent >= 0) last_send[size_t(g)] = last_receive[size_t(to)] = sent;
    }
}

std::vector<int> Composer::close() {
  if (deferred()) {
    std::vector<int> ready(size_t(m_sim.gpms()));
    for (int g = 0; g < m_sim.gpms(); ++g) ready[size_t(g)] = m_sim.last_unit(g);
    if (m_algorithm == CompositionAlgorithm::binary_swap) binary_swap(ready);
    else pairwise(ready);
  }
  return std::exchange(m_units, {});
}

}  // namespace oovr
