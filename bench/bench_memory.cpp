// Memory-system throughput: line accesses per second through L1, L2, remote
// cache and placement, on one core. Target (issue 4): at least 50 million.
//
// The access stream is the courtyard's real texture traffic (a FrameTrace at
// 1280x1024) replayed by 4 GPMs that own interleaved screen tiles, plus its
// depth and colour lines; and, for the worst case, uniformly random lines.
#include <benchmark/benchmark.h>

#include "oovr/core/rng.h"
#include "oovr/memory/memory_system.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/builtin.h"

namespace {

using namespace oovr;

struct TraceStream {
  Scene scene;
  FrameOutput frame;
  std::vector<std::vector<LineAccess>> units;  // one per tile record
  std::vector<int> gpm;
};

const TraceStream& stream() {
  static TraceStream* s = [] {
    auto* t = new TraceStream{BuiltinScenes::find("courtyard")->make(), {}, {}, {}};
    StereoRig rig;
    rig.eye_width = 640;
    rig.eye_height = 1024;
    t->frame = render_frame(t->scene, make_stereo_view(t->scene.camera, 0, rig), PipelineSettings{});
    return t;
  }();
  return *s;
}

void trace_replay(benchmark::State& state) {
  const TraceStream& t = stream();
  const MemorySpec spec = MemorySpec::from_config(Config{});
  AddressMap map(spec.page, spec.line);
  const SceneLayout layout(map, t.scene, t.frame.trace);
  std::vector<std::vector<LineAccess>> units;
  std::vector<int> owner;
  for (const TileWork& w : t.frame.trace.tiles) {
    std::vector<LineAccess> u;
    for (uint32_t k = 0; k < w.tex_count; ++k)
      u.push_back({layout.texture_line(t.frame.trace.tex_lines[w.tex_begin + k]), Category::texture, false});
    for (int l = 0; l < layout.lines_per_tile(); ++l) {
      if (w.depth_read_mask & (1u << l))
        u.push_back({layout.frame_line(layout.depth_region(), w.tile_x, w.tile_y, l), Category::depth, false});
      if (w.colour_read_mask & (1u << l))
        u.push_back({layout.frame_line(layout.colour_region(), w.tile_x, w.tile_y, l), Category::colour, false});
      if (w.depth_write_mask & (1u << l))
        u.push_back({layout.frame_line(layout.depth_region(), w.tile_x, w.tile_y, l), Category::depth, true});
      if (w.colour_write_mask & (1u << l))
        u.push_back({layout.frame_line(layout.colour_region(), w.tile_x, w.tile_y, l), Category::colour, true});
    }
    units.push_back(std::move(u));
    owner.push_back((w.tile_x + w.tile_y) % 4);
  }
  uint64_t accesses = 0;
  for (auto _ : state) {
    MemorySystem mem(spec, map);
    UnitTraffic u;
    for (size_t i = 0; i < units.size(); ++i) {
      mem.access(owner[i], int(i % 8), units[i], u);
      accesses += units[i].size();
    }
    benchmark::DoNotOptimize(mem.totals().accesses);
  }
  state.counters["accesses/s"] = benchmark::Counter(double(accesses), benchmark::Counter::kIsRate);
}

void random_lines(benchmark::State& state) {
  const MemorySpec spec = MemorySpec::from_config(Config{});
  AddressMap map(spec.page, spec.line);
  map.add("buffer", Category::texture, 64ull << 20);
  std::vector<LineAccess> a(1 << 16);
  Rng rng(1);
  for (auto& x : a) x = {uint64_t(rng.below(uint32_t(64ull << 20))) & ~uint64_t(127), Category::texture, false};
  MemorySystem mem(spec, map);
  UnitTraffic u;
  uint64_t accesses = 0;
  int g = 0;
  for (auto _ : state) {
    mem.access(g, g % 8, a, u);
    g = (g + 1) % 4;
    accesses += a.size();
  }
  state.counters["accesses/s"] = benchmark::Counter(double(accesses), benchmark::Counter::kIsRate);
}

BENCHMARK(trace_replay)->Unit(benchmark::kMillisecond);
BENCHMARK(random_lines)->Unit(benchmark::kMillisecond);

}  // namespace
