// The quad sampler (four pixels' coordinates in SIMD lanes) against the
// scalar one, pixel by pixel: the same colours bit for bit, the same lines
// in the same order and the same sample counts, since traces and images must
// not change with how the pipeline computes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <tuple>

#include "oovr/pipeline/sampler.h"

namespace {

using namespace oovr;

uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }

TEST(Sampler, Floor4IsStdFloorBitForBit) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> xs = {0.0f, -0.0f, 0.5f,       -0.5f,       1.0f,        -1.0f,       -1e-30f, 1e-30f,
                           2.5f, -2.5f, 8388607.5f, -8388607.5f, 8388608.0f,  -8388608.0f, 1e20f,   -1e20f,
                           3e9f, -3e9f, inf,        -inf,        0.99999994f, -0.99999994f};
  std::mt19937 rng(11);
  for (int i = 0; i < 4000; ++i) {
    float f;
    const uint32_t r = rng();
    std::memcpy(&f, &r, 4);  // any float, NaNs excepted below
    if (!std::isnan(f)) xs.push_back(f);
    xs.push_back(float(int32_t(rng() % 2000001) - 1000000) / 256.0f);  // near integers, both signs
  }
  for (size_t i = 0; i + 4 <= xs.size(); i += 4) {
    const detail::Float4 x{xs[i], xs[i + 1], xs[i + 2], xs[i + 3]};
    const detail::Float4 y = detail::floor4(x);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(bits(y[k]), bits(std::floor(xs[i + size_t(k)]))) << xs[i + size_t(k)];
  }
  const detail::Float4 n = detail::floor4(detail::Float4{nan, nan, 1.5f, nan});
  EXPECT_TRUE(std::isnan(n[0]) && std::isnan(n[1]) && std::isnan(n[3]));
  EXPECT_EQ(n[2], 1.0f);
}

Texture noise_texture(int w, int h, Wrap wrap, bool mipmapped, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> px(size_t(w) * size_t(h) * 4);
  for (auto& b : px) b = uint8_t(rng());
  return make_texture("noise", "noise", w, h, std::move(px), wrap, mipmapped);
}

TEST(Sampler, QuadSamplesAreThoseOfFourPixels) {
  // Power-of-two and odd sizes, repeat and clamp, with and without mips.
  struct Case {
    int w, h;
    Wrap wrap;
    bool mips;
  };
  const Case cases[] = {{256, 128, Wrap::repeat, true},
                        {37, 91, Wrap::repeat, true},
                        {64, 64, Wrap::clamp_to_edge, true},
                        {45, 30, Wrap::clamp_to_edge, true},
                        {128, 128, Wrap::repeat, false}};
  std::mt19937 rng(5);
  const auto uniform = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) / float(1u << 24); };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  int compared = 0, few_line_quads = 0;
  for (size_t ci = 0; ci < std::size(cases); ++ci) {
    const Case& c = cases[ci];
    const Texture tex = noise_texture(c.w, c.h, c.wrap, c.mips, uint32_t(ci + 1));
    const detail::SamplerTexture st(uint32_t(ci), tex, 8, 4);
    for (int q = 0; q < 3000; ++q) {
      // Quads near and far outside [0, 1], steep and flat, exact levels
      // (a lambda of 2.0 fetches one level) and magnification.
      const float span = q % 7 == 0 ? 1e4f : 3.0f;
      const float u0 = uniform(-span, span), v0 = uniform(-span, span);
      // Every fourth quad spans a texel or less, so that each level's taps
      // often lie in one block (add_quad_lines adds its line once).
      const float d = q % 4 == 1 ? 0.002f : 0.05f;
      const float du = uniform(-d, d), dv = uniform(-d, d);
      float u[4] = {u0, u0 + du, u0 + dv * 0.5f, u0 + du + dv * 0.5f};
      float v[4] = {v0, v0 - dv, v0 + du, v0 + du - dv};
      float lambda = uniform(-2.0f, float(st.max_level) + 2.0f);
      if (q % 5 == 0) lambda = std::floor(lambda);
      const unsigned live = 1u + rng() % 15u;
      for (int p = 0; p < 4; ++p)
        if (!(live & (1u << p)) && q % 3 == 0) u[p] = v[p] = nan;  // helpers may be anything
      detail::QuadLines ql, sl;
      std::vector<TexLine> quad_lines, scalar_lines;
      uint32_t quad_samples = 0, scalar_samples = 0;
      detail::Float4 got4[4];
      detail::sample_quad(st, detail::Float4{u[0], u[1], u[2], u[3]}, detail::Float4{v[0], v[1], v[2], v[3]}, lambda, live, &ql,
                          quad_samples, got4);
      ql.flush(quad_lines);
      for (int p = 0; p < 4; ++p) {
        if (!(live & (1u << p))) continue;
        const detail::Rgba got = detail::to_rgba(got4[p]);
        const detail::Rgba want = detail::to_rgba(detail::sample_lod(st, u[p], v[p], lambda, &sl, scalar_samples));
        ASSERT_EQ(bits(got.r), bits(want.r)) << "case " << ci << " quad " << q << " pixel " << p;
        ASSERT_EQ(bits(got.g), bits(want.g));
        ASSERT_EQ(bits(got.b), bits(want.b));
        ASSERT_EQ(bits(got.a), bits(want.a));
        ++compared;
      }
      sl.flush(scalar_lines);
      ASSERT_EQ(quad_lines, scalar_lines) << "case " << ci << " quad " << q;
      ASSERT_EQ(quad_samples, scalar_samples);
      // The trace alone's lines and lookups (the plan of sample_quad_lines).
      detail::QuadLines pl;
      std::vector<TexLine> plan_lines;
      uint32_t plan_samples = 0;
      detail::sample_quad_lines(st, detail::Float4{u[0], u[1], u[2], u[3]}, detail::Float4{v[0], v[1], v[2], v[3]}, lambda, live,
                                &pl, plan_samples);
      pl.flush(plan_lines);
      ASSERT_EQ(plan_lines, scalar_lines) << "case " << ci << " quad " << q;
      ASSERT_EQ(plan_samples, scalar_samples);
      few_line_quads += plan_lines.size() <= 2;
    }
  }
  EXPECT_GT(compared, 20000);
  EXPECT_GT(few_line_quads, 1000);  // quads of one block a level (at most two lines) were met
}

// A quad's lines: each line's first add, in order, whatever the textures
// (searched among their own texture's lines) and however many (past 64
// lines, the rest sorted after them).
TEST(Sampler, QuadLinesKeepEachLinesFirstAddInOrder) {
  std::mt19937 rng(17);
  for (int round = 0; round < 20000; ++round) {
    // Few textures and lines, so that textures come back after others and
    // lines repeat; some rounds read more than eight textures or add more
    // than 64 lines.
    const uint32_t textures = 1 + rng() % (round % 10 == 0 ? 12 : 4);
    const uint32_t per_texture = 1 + rng() % (round % 25 == 0 ? 40 : 6);
    const int adds = 1 + int(rng() % (round % 25 == 0 ? 300 : 24));
    detail::QuadLines ql;
    std::vector<TexLine> added;
    for (int i = 0; i < adds; ++i) {
      const TexLine l = make_tex_line(rng() % textures * 7919u, rng() % per_texture);
      ql.add(l);
      added.push_back(l);
      if (rng() % 3 == 0) {  // the same line again at once
        ql.add(l);
        added.push_back(l);
      }
    }
    std::vector<TexLine> want, rest;
    for (const TexLine l : added) {
      if (std::find(want.begin(), want.end(), l) != want.end() || std::find(rest.begin(), rest.end(), l) != rest.end()) continue;
      (want.size() < 64 ? want : rest).push_back(l);
    }
    std::sort(rest.begin(), rest.end());
    want.insert(want.end(), rest.begin(), rest.end());
    std::vector<TexLine> got;
    ql.flush(got);
    ASSERT_EQ(got, want) << "round " << round;
    // Flushed, it starts again.
    ql.add(make_tex_line(1, 1));
    got.clear();
    ql.flush(got);
    ASSERT_EQ(got, std::vector<TexLine>{make_tex_line(1, 1)});
  }
}

// The trace alone's level of detail (lod_for_levels, without log2f where
// the exponent decides) picks the levels, and their count, that log2f's
// would, for every exponent, at the edges of the range it takes and past
// them (powers of two and their neighbours, where log2f may round to an
// integer), for zero, subnormals, negatives, infinities and NaN, on
// textures of 1 to 14 levels and one without mipmaps; and whole footprints,
// trilinear and anisotropic, give the same probes, axis and levels.
TEST(Sampler, TheTraceAlonesLevelOfDetailChoosesTheLevelsLog2fWould) {
  std::vector<detail::SamplerTexture> textures;
  std::vector<Texture> keep;
  for (const auto& [w, h, mips] : std::vector<std::tuple<int, int, bool>>{
           {1, 1, true}, {2, 1, true}, {16, 8, true}, {256, 256, true}, {8192, 1, true}, {64, 64, false}}) {
    keep.push_back(noise_texture(w, h, Wrap::repeat, mips, 3));
    textures.emplace_back(0, keep.back(), 8, 4);
  }
  EXPECT_EQ(textures[4].max_level, 13);
  const auto same = [](const detail::LevelChoice& a, const detail::LevelChoice& b) {
    if (a.count != b.count) return false;
    for (int i = 0; i < a.count; ++i)
      if (a.level[i] != b.level[i]) return false;
    return true;
  };
  // Zero, the smallest, the middle and the largest mantissas, each end of
  // the range the exponent decides with its neighbours, and random ones.
  std::vector<uint32_t> mantissas = {0, 1, 2, 1u << 22, (1u << 23) - 2, (1u << 23) - 1};
  for (const uint32_t end : {1u << 11, (1u << 23) - (1u << 11)})
    for (uint32_t m = end - 2; m <= end + 1; ++m) mantissas.push_back(m);
  std::mt19937 rng(5);
  for (int i = 0; i < 64; ++i) mantissas.push_back(rng() & 0x7fffffu);
  std::vector<float> xs;
  for (uint32_t sign = 0; sign < 2; ++sign)
    for (uint32_t e = 0; e < 256; ++e)
      for (const uint32_t m : mantissas) xs.push_back(std::bit_cast<float>(sign << 31 | e << 23 | m));
  int fast = 0;
  for (const float x : xs) {
    const float lod = detail::lod_for_levels(x);
    if (bits(lod) != bits(std::log2(x))) ++fast;
    for (const detail::SamplerTexture& t : textures)
      ASSERT_TRUE(same(detail::choose_levels(t, lod), detail::choose_levels(t, std::log2(x))))
          << "x = " << x << " (bits " << std::hex << bits(x) << std::dec << "), max level " << t.max_level;
  }
  EXPECT_GT(fast, 15000);  // the exponent decided most of the 19,968 positive ones
  // A footprint all but a line (its axes' ratio past INT_MAX, or infinite)
  // takes the most probes; the ratio's conversion to int was undefined (x86
  // gave one probe). Axes both infinite (a ratio of NaN) take one.
  const detail::SamplerTexture& mipmapped = textures[3];
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(detail::footprint(mipmapped, detail::Derivs{1, 0, 1e-12f, 0}, 16).probes, 16);
  EXPECT_EQ(detail::footprint(mipmapped, detail::Derivs{inf, 0, 1e-3f, 0}, 16).probes, 16);
  EXPECT_EQ(detail::footprint(mipmapped, detail::Derivs{inf, 0, inf, 0}, 16).probes, 1);
  EXPECT_EQ(detail::footprint(mipmapped, detail::Derivs{1, 0, 0.25f, 0}, 16).probes, 4);
  for (int i = 0; i < 200000; ++i) {
    const auto any = [&] { return float(int32_t(rng() % 2000001) - 1000000) / float(1u << (rng() % 30)); };
    const detail::Derivs d{any(), any(), any(), any()};
    const detail::SamplerTexture& t = textures[size_t(rng() % textures.size())];
    for (const int aniso : {1, 16}) {
      const detail::Footprint a = detail::footprint(t, d, aniso), b = detail::footprint<true>(t, d, aniso);
      ASSERT_EQ(a.probes, b.probes);
      ASSERT_EQ(bits(a.du), bits(b.du));
      ASSERT_EQ(bits(a.dv), bits(b.dv));
      ASSERT_TRUE(same(detail::choose_levels(t, a.lambda), detail::choose_levels(t, b.lambda))) << "round " << i;
    }
  }
}

}  // namespace
