// The hot paths of a simulated frame, one at a time (docs/performance.md,
// "Hot paths"): geometry and set-up, texture sampling with its footprint,
// cache lookups, and the event engine. The rasteriser as a whole is
// bench_pipeline.cpp, the memory replay bench_memory.cpp and a scheme's
// replay bench_schemes.cpp.
#include <benchmark/benchmark.h>

#include "oovr/core/rng.h"
#include "oovr/memory/cache.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/sampler.h"
#include "oovr/scene/builtin.h"
#include "oovr/timing/engine.h"

namespace {

using namespace oovr;

const Scene& courtyard() {
  static const Scene* s = new Scene(BuiltinScenes::find("courtyard")->make());
  return *s;
}

// Geometry and set-up: a frame of 32x16 pixels, where every object is still
// transformed, projected, clipped, culled, set up and binned, and almost
// nothing is rasterised.
void setup(benchmark::State& state) {
  const Scene& s = courtyard();
  StereoRig rig;
  rig.eye_width = 16;
  rig.eye_height = 16;
  const StereoView view = make_stereo_view(s.camera, 60, rig);
  PipelineSettings p;
  p.threads = 1;
  uint64_t triangles = 0;
  for (auto _ : state) {
    const FrameOutput out = render_frame(s, view, p, 60);
    for (const auto& o : out.trace.objects) triangles += o.triangles;
  }
  state.counters["triangles/s"] = benchmark::Counter(double(triangles), benchmark::Counter::kIsRate);
}

// The courtyard's first mip-mapped texture, prepared for sampling with the
// Table 1 lines (8x4 texel blocks).
detail::SamplerTexture sampled_texture() {
  const Scene& s = courtyard();
  size_t ti = 0;
  while (ti + 1 < s.textures.size() && !s.textures[ti].mipmapped) ++ti;
  return detail::SamplerTexture(uint32_t(ti), s.textures[ti], 8, 4);
}

// One pixel's texture sample with its quad's footprint (trilinear, or 16x
// anisotropic) on the courtyard's first mip-mapped texture, at minifying
// scales and random positions, recording the lines touched.
void texture_sample(benchmark::State& state, int aniso) {
  const detail::SamplerTexture tex = sampled_texture();
  Rng rng(7);
  struct Probe {
    float u, v;
    detail::Derivs d;
  };
  std::vector<Probe> probes(4096);
  for (auto& p : probes) {
    const float scale = float(1 + rng.below(16)) / float(tex.levels[0].width);
    const float skew = float(1 + rng.below(8));  // footprints up to 8:1
    p = {float(rng.below(1 << 16)) / 65536.0f, float(rng.below(1 << 16)) / 65536.0f, {scale, 0, 0, scale * skew}};
  }
  detail::QuadLines lines;
  uint32_t samples = 0;
  float sum = 0;
  uint64_t n = 0;
  for (auto _ : state) {
    for (const Probe& p : probes) {
      const detail::Footprint f = detail::footprint(tex, p.d, aniso);
      sum += detail::sample(tex, p.u, p.v, f, &lines, samples).r;
      lines.clear();
    }
    n += probes.size();
  }
  benchmark::DoNotOptimize(sum);
  state.counters["pixels/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
  state.counters["bilinear/pixel"] = double(samples) / double(n);
}

// Whole quads (the pipeline's trilinear path) on the same texture: a random
// point and its neighbours one pixel right and down at a minifying scale.
struct QuadProbe {
  detail::Float4 u, v;
  detail::Derivs d;
};
std::vector<QuadProbe> quad_probes(const detail::SamplerTexture& tex) {
  Rng rng(7);
  std::vector<QuadProbe> probes(1024);
  for (auto& p : probes) {
    const float scale = float(1 + rng.below(16)) / float(tex.levels[0].width);
    const float u = float(rng.below(1 << 16)) / 65536.0f, v = float(rng.below(1 << 16)) / 65536.0f;
    p = {detail::Float4{u, u + scale, u, u + scale}, detail::Float4{v, v, v + scale, v + scale}, {scale, 0, 0, scale}};
  }
  return probes;
}

// Runs `sample(tex, probe, footprint, lines, lookups)` on every quad, its
// lines cleared after each, and reports pixels a second and bilinear
// lookups a pixel.
template <class Sample>
void sample_quads(benchmark::State& state, Sample sample) {
  const detail::SamplerTexture tex = sampled_texture();
  const std::vector<QuadProbe> probes = quad_probes(tex);
  detail::QuadLines lines;
  uint32_t samples = 0;
  uint64_t n = 0;
  for (auto _ : state) {
    for (const QuadProbe& p : probes) {
      sample(tex, p, detail::footprint(tex, p.d, 1), lines, samples);
      lines.clear();
    }
    n += 4 * probes.size();
  }
  state.counters["pixels/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
  state.counters["bilinear/pixel"] = double(samples) / double(n);
}

// The quads sampled together with their isotropic footprint by sample_quad.
void texture_sample_quad(benchmark::State& state) {
  float sum = 0;
  detail::Float4 out[4];
  sample_quads(state, [&](const detail::SamplerTexture& tex, const QuadProbe& p, const detail::Footprint& f,
                          detail::QuadLines& lines, uint32_t& samples) {
    detail::sample_quad(tex, p.u, p.v, f.lambda, 0xfu, &lines, samples, out);
    sum += out[0][0] + out[3][1];
  });
  benchmark::DoNotOptimize(sum);
}

// The same quads' lines and lookups without the image (sample_quad_lines:
// the trace alone, as simulate draws it): no texel fetched or filtered.
void texture_quad_lines(benchmark::State& state) {
  sample_quads(state, [](const detail::SamplerTexture& tex, const QuadProbe& p, const detail::Footprint& f,
                         detail::QuadLines& lines, uint32_t& samples) {
    detail::sample_quad_lines(tex, p.u, p.v, f.lambda, 0xfu, &lines, samples);
    benchmark::DoNotOptimize(lines);
  });
}

// Cache lookups: an L1 (128 KB, 4 ways) and an L2 (1 MB, 16 ways) of the
// paper's Table 1 with 128-byte lines; a stream that fits (hits) and one
// over 64 MB (every access a miss and an LRU eviction).
void cache_lookup(benchmark::State& state, uint64_t bytes, int ways, uint64_t footprint_lines) {
  CacheSpec spec;
  spec.size = Bytes{bytes};
  spec.ways = ways;
  spec.replacement = "lru";
  Cache c(spec, 128, "bench");
  std::vector<uint64_t> lines(1 << 16);
  Rng rng(3);
  for (auto& l : lines) l = rng.below(uint32_t(footprint_lines));
  Cache::Eviction ev;
  uint64_t n = 0, hits = 0;
  for (auto _ : state) {
    for (uint64_t l : lines) hits += c.access(l, false, Category::texture, ev);
    n += lines.size();
  }
  benchmark::DoNotOptimize(hits);
  state.counters["lookups/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
  state.counters["hit rate"] = double(hits) / double(n);
}

// The event engine: 4 queues (GPMs) of units demanding shader, texture and
// DRAM resources of their GPM and one shared link, run to the end; what a
// frame's timing costs per unit.
void event_engine(benchmark::State& state) {
  const int units = int(state.range(0));
  Rng rng(5);
  uint64_t n = 0;
  for (auto _ : state) {
    state.PauseTiming();
    TimingEngine e;
    std::vector<int> queue, shader, texture, dram;
    for (int g = 0; g < 4; ++g) {
      queue.push_back(e.add_queue("gpm" + std::to_string(g)));
      shader.push_back(e.add_resource("shader", 1e12));
      texture.push_back(e.add_resource("texture", 1e11));
      dram.push_back(e.add_resource("dram", 1e12));
    }
    const int link = e.add_resource("link", 64e9);
    for (int i = 0; i < units; ++i) {
      const int g = i % 4;
      TimingEngine::Unit u;
      u.queue = queue[size_t(g)];
      u.demand = {{shader[size_t(g)], double(1 + rng.below(1000)) * 1e3},
                  {texture[size_t(g)], double(1 + rng.below(1000)) * 1e2},
                  {dram[size_t(g)], double(1 + rng.below(1000)) * 1e3}};
      if (rng.below(4) == 0) u.demand.push_back({link, double(1 + rng.below(1000)) * 1e2});
      (void)e.add_unit(std::move(u));
    }
    state.ResumeTiming();
    benchmark::DoNotOptimize(e.run().makespan);
    n += uint64_t(units);
  }
  state.counters["units/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
}

BENCHMARK(setup)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(texture_sample, trilinear, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(texture_sample, aniso16, 16)->Unit(benchmark::kMicrosecond);
BENCHMARK(texture_sample_quad)->Unit(benchmark::kMicrosecond);
BENCHMARK(texture_quad_lines)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(cache_lookup, l1_hits, 128 << 10, 4, 512)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(cache_lookup, l2_misses, 1 << 20, 16, 1 << 19)->Unit(benchmark::kMicrosecond);
BENCHMARK(event_engine)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace
