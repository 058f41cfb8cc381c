// gpupd (not in the OO-VR paper): Kim, Kim, Park, Kim and Kim, "GPUpd: A
// Fast and Scalable Multi-GPU Architecture Using Cooperative Projection and
// Distribution", MICRO 2017. Sort-first: each GPM owns a screen region (a
// vertical strip of tile columns, sfr-v's). Draws are taken in batches, and
// each batch goes through three phases:
//
//   projection    every GPM receives every draw of the batch and projects
//                 its 1/N share of each draw's primitives (the share of the
//                 vertices and of the vertex and index buffers, in draw
//                 order; assembly, clipping, culling and bounding boxes for
//                 its share of the triangles);
//   distribution  the IDs of the projected primitives (4 bytes each) go to
//                 the GPMs whose regions they overlap, in API order: the
//                 GPMs send one after the other (GPM 0's lists, then GPM
//                 1's, ...), on the links;
//   rendering     each GPM, once the exchange is over, renders the
//                 primitives it received in draw order: their vertices
//                 shaded in full, their triangles set up, its region's
//                 tiles rasterised and shaded.
//
// Switches: `gpupd.batching` (draws taken `gpupd.batch_draws` or
// `gpupd.batch_primitives` at a time, whichever fills first: CHOPIN's
// reimplementation of GPUpd uses 512 and 4,096; off: one draw per batch)
// and `gpupd.runahead` (a GPM projects the next batch before it renders
// this one, as GPUpd's runahead execution; off: it projects a batch after
// rendering the one before).
//
// Derived from the trace: a draw's primitives overlapping a region are
// counted as its set-up triangles in the region's tile records (a triangle
// over several of a region's tiles is counted in each, as the baseline's
// hand-over of set-up triangles counts them); a GPM receiving some of a
// draw's primitives shades the same share of its vertices (at most all).
//
// Assumed where the paper is silent or oovr cannot say: the regions
// (vertical strips), 4 bytes per primitive ID, and the projection running
// `gpupd.projection_cost` of the vertex shader (1: the whole shader; the
// paper runs only the position part, whose share oovr's traces do not
// give).
#include <algorithm>
#include <cmath>
#include <string>

#include "oovr/core/config_sections.h"
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

struct GpupdSettings {
  bool batching = true;
  int batch_draws = 512;
  int batch_primitives = 4096;
  bool runahead = true;
  double projection_cost = 1;

  static GpupdSettings from_config(const Config& c) {
    GpupdSettings s;
    s.batching = c.get_bool("gpupd.batching", s.batching);
    s.batch_draws = int(c.get_int("gpupd.batch_draws", s.batch_draws, 1, 1 << 20));
    s.batch_primitives = int(c.get_int("gpupd.batch_primitives", s.batch_primitives, 1, 1 << 30));
    s.runahead = c.get_bool("gpupd.runahead", s.runahead);
    s.projection_cost = c.get_double("gpupd.projection_cost", s.projection_cost, 0, 1);
    return s;
  }
};

constexpr uint64_t kPrimitiveIdBytes = 4;

class Gpupd final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    const GpupdSettings& set = in.spec->own<GpupdSettings>("gpupd");
    FrameSim sim(in);
    const int n = sim.gpms();
    const FrameTrace& f = sim.frame();
    const size_t draws = sim.draws(f).size();
    const std::vector<ObjectRecords> records = records_by_object(f, draws);
    // Each draw's records and primitives per region.
    std::vector<std::vector<std::vector<const TileWork*>>> mine(draws, std::vector<std::vector<const TileWork*>>(size_t(n)));
    std::vector<std::vector<uint64_t>> prims(draws, std::vector<uint64_t>(size_t(n), 0));
    for (uint32_t o = 0; o < draws; ++o)
      for (int e = 0; e < 2; ++e)
        for (const TileWork* r : records[o].eye[e]) {
          const int g = vertical_strip_owner(r->tile_x, f.tiles_x, n);
          mine[o][size_t(g)].push_back(r);
          prims[o][size_t(g)] += r->triangles;
        }
    // The batches, in draw order.
    std::vector<std::pair<uint32_t, uint32_t>> batches;  // [first, end)
    for (uint32_t o = 0; o < draws;) {
      uint32_t end = o + 1;
      uint64_t tris = f.objects[o].triangles;
      if (set.batching)
        while (end < draws && end - o < uint32_t(set.batch_draws) && tris < uint64_t(set.batch_primitives))
          tris += f.objects[end++].triangles;
      batches.push_back({o, end});
      o = end;
    }

    std::vector<std::vector<int>> received(draws, std::vector<int>(size_t(n), -1));  // command units
    // Projection and distribution of batch b; returns the units rendering
    // waits for (the end of the exchange, and every projection).
    const auto project = [&](size_t b) {
      std::vector<std::vector<int>> projected(static_cast<size_t>(n));
      for (uint32_t o = batches[b].first; o < batches[b].second; ++o)
        for (int g = 0; g < n; ++g) {
          received[o][size_t(g)] = sim.command(g);
          const uint64_t share = uint64_t(std::llround(double(f.objects[o].triangles) / n));
          projected[size_t(g)].push_back(sim.geometry_part(g, o, double(g) / n, double(g + 1) / n, set.projection_cost, share));
        }
      // Each sender's share (1/N) of the batch's primitives in each region.
      std::vector<uint64_t> bytes(size_t(n), 0);
      for (int g = 0; g < n; ++g) {
        double ids = 0;
        for (uint32_t o = batches[b].first; o < batches[b].second; ++o) ids += double(prims[o][size_t(g)]) / n;
        bytes[size_t(g)] = uint64_t(std::llround(ids)) * kPrimitiveIdBytes;
      }
      std::vector<int> step;  // the previous sender's transfers (or what it waited for)
      for (int p = 0; p < n; ++p) {
        std::vector<int> after = step;
        after.insert(after.end(), projected[size_t(p)].begin(), projected[size_t(p)].end());
        std::vector<int> sent;
        for (int g = 0; g < n; ++g)
          if (g != p && bytes[size_t(g)]) sent.push_back(sim.transfer(p, g, bytes[size_t(g)], Category::command, after));
        step = sent.empty() ? after : sent;
      }
      for (const auto& units : projected) step.insert(step.end(), units.begin(), units.end());
      // For a timeline: each GPM's projection of the batch, its first draw
      // received to its last share projected.
      for (int g = 0; g < n && !projected[size_t(g)].empty(); ++g)
        sim.mark_span("batch " + std::to_string(b) + " projection", "projection", g, received[batches[b].first][size_t(g)],
                      projected[size_t(g)].back(), {{"batch", double(b)}});
      return step;
    };
    const auto render = [&](size_t b, const std::vector<int>& exchanged) {
      std::vector<std::pair<int, int>> span(size_t(n), {-1, -1});  // per GPM: its first and last rendering unit
      for (uint32_t o = batches[b].first; o < batches[b].second; ++o) {
        std::vector<FrameSim::TileJob> jobs;
        for (int g = 0; g < n; ++g) {
          sim.use_draw(g, received[o][size_t(g)]);
          if (mine[o][size_t(g)].empty()) continue;
          const uint64_t got = prims[o][size_t(g)];
          const double share = std::min(1.0, double(got) / double(std::max<uint32_t>(1, f.objects[o].triangles)));
          const int geo = sim.geometry_part(g, o, 0, share, 1, got, exchanged);
          if (span[size_t(g)].first < 0) span[size_t(g)].first = geo;
          jobs.push_back({g, mine[o][size_t(g)], 0, {geo}});
        }
        const std::vector<int> units = sim.tiles_together(jobs, f);
        for (size_t j = 0; j < jobs.size(); ++j) span[size_t(jobs[j].gpm)].second = units[j];
        for (int g = 0; g < n; ++g) sim.end_draw(g);
      }
      for (int g = 0; g < n; ++g)
        if (span[size_t(g)].first >= 0)
          sim.mark_span("batch " + std::to_string(b) + " rendering", "rendering", g, span[size_t(g)].first,
                        span[size_t(g)].second, {{"batch", double(b)}});
    };
    std::vector<int> next = batches.empty() ? std::vector<int>{} : project(0);
    for (size_t b = 0; b < batches.size(); ++b) {
      const std::vector<int> now = std::move(next);
      if (set.runahead && b + 1 < batches.size()) next = project(b + 1);
      render(b, now);
      if (!set.runahead && b + 1 < batches.size()) next = project(b + 1);
    }
    return sim.finish("gpupd");
  }
};

const ConfigSections::Add settings(
    "gpupd", {"GPUpd's settings (Kim et al., MICRO 2017)",
              nullptr,
              {{"gpupd.batching", "draws taken in batches (true) or one at a time"},
               {"gpupd.batch_draws", "draws that close a batch (512, CHOPIN's reimplementation of GPUpd)"},
               {"gpupd.batch_primitives", "primitives that close a batch (4096, CHOPIN's reimplementation of GPUpd)"},
               {"gpupd.runahead", "a GPM projects the next batch before rendering this one (GPUpd's runahead execution)"},
               {"gpupd.projection_cost",
                "share of the vertex shader the projection runs (1, assumed: the traces do not give "
                "the position part's)"}},
              true,
              [](const Config& c) { return std::any(GpupdSettings::from_config(c)); }});

const Schemes::Add reg("gpupd",
                       {"GPUpd: cooperative projection, primitive distribution in API order, sort-first strips (MICRO 2017)",
                        [] { return std::make_unique<Gpupd>(); },
                        140,
                        {"gpupd"}});

}  // namespace
}  // namespace oovr
