// Texture sampling as OpenGL 4.5 (Section 8.14) specifies it for
// GL_LINEAR_MIPMAP_LINEAR minification and GL_LINEAR magnification, with
// optional anisotropic filtering (EXT_texture_filter_anisotropic), recording
// the cache lines each fetch touches. Internal to the pipeline.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "oovr/pipeline/frame_trace.h"
#include "oovr/pipeline/tiled_layout.h"
#include "oovr/scene/texture.h"

namespace oovr::detail {

// Lines touched by one 2x2 quad, merged: a texture unit coalesces a quad's
// requests for the same line.
class QuadLines {
 public:
  void clear() {
    m_count = 0;
    m_last = ~TexLine(0);
    m_texture = kNone;
    m_from = 0;
    m_textures = 0;
  }
  [[gnu::always_inline]] void add(TexLine l) {
    if (l == m_last) return;  // most repeats are of the line just added
    m_last = l;
    // A line is searched for among its texture's lines alone: the quad's
    // other textures' lines differ from it in their texture.
    if (tex_line_texture(l) != m_texture) [[unlikely]]
      begin_texture(tex_line_texture(l));
    for (int i = m_from; i < m_count; ++i)
      if (m_lines[i] == l) return;
    if (m_count < kMax) {
      m_lines[m_count++] = l;
    } else {
      m_overflow.push_back(l);  // rare: huge footprints (extreme anisotropy)
    }
  }
  template <class Out>
  [[gnu::always_inline]] void flush(Out& out) {
    out.insert(out.end(), m_lines, m_lines + m_count);
    if (!m_overflow.empty()) [[unlikely]]
      flush_overflow(out);
    clear();
  }

 private:
  static constexpr int kMax = 64, kTextures = 8;
  static constexpr uint32_t kNone = ~0u;  // no texture is number 2^32 - 1
  // The lines past kMax, sorted, each once, less those in m_lines.
  template <class Out>
  [[gnu::noinline]] void flush_overflow(Out& out) {
    std::sort(m_overflow.begin(), m_overflow.end());
    m_overflow.erase(std::unique(m_overflow.begin(), m_overflow.end()), m_overflow.end());
    for (TexLine l : m_overflow)
      if (std::find(m_lines, m_lines + m_count, l) == m_lines + m_count) out.push_back(l);
    m_overflow.clear();
  }
  // Lines of `texture` follow: searched for from the first line added
  // after this call if the quad has not read the texture before, else
  // (or past kTextures textures) from its first line.
  [[gnu::noinline]] void begin_texture(uint32_t texture) {
    bool seen = m_textures > kTextures;
    for (int i = 0; i < m_textures && i < kTextures; ++i) seen = seen || m_seen[i] == texture;
    m_from = seen ? 0 : m_count;
    if (!seen) {
      if (m_textures < kTextures) m_seen[m_textures] = texture;
      ++m_textures;  // at most kTextures + 1: `seen` holds from then on
    }
    m_texture = texture;
  }
  TexLine m_lines[kMax];
  int m_count = 0;
  TexLine m_last = ~TexLine(0);
  uint32_t m_texture = kNone;  // the texture of the lines being added
  int m_from = 0;              // where their search begins
  // The textures the quad has read, in order (m_textures of them; more
  // than kTextures: too many to list, any may be read again).
  uint32_t m_seen[kTextures];
  int m_textures = 0;
  std::vector<TexLine> m_overflow;
};

// Pixels set in a quad's 4-bit mask. A table: without -mpopcnt (oovr is
// built for any x86-64) the builtin is a library call.
inline uint32_t pixels_in(unsigned mask) {
  static constexpr uint8_t kPixels[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
  return kPixels[mask & 15u];
}

struct LevelView {
  int width, height;
  int wrap_mask_x, wrap_mask_y;  // size - 1 for power-of-two sizes, else -1
  int blocks_x;
  uint32_t first_line;  // line index of the level's first block
  const uint8_t* rgba;
};

// A texture prepared for sampling: per-level sizes and line offsets.
struct SamplerTexture {
  uint32_t id = 0;
  bool repeat = true;
  bool mipmapped = true;
  int max_level = 0;
  int block_w = 8, block_h = 4;
  int block_shift_x = 3, block_shift_y = 2;
  std::vector<LevelView> levels;
  // Textures of one shape (the same wrapping, mipmapping, line blocks and
  // levels' sizes) have the same footprints, levels and texel blocks at
  // the same coordinates; only their lines' bases differ. Set by the
  // renderer per frame (0 until then: a shape of its own is not assumed).
  uint32_t shape = 0;

  SamplerTexture(uint32_t id_, const Texture& t, int bw, int bh) : id(id_), block_w(bw), block_h(bh) {
    repeat = t.wrap == Wrap::repeat;
    mipmapped = t.mipmapped && t.levels.size() > 1;
    block_shift_x = __builtin_ctz(unsigned(bw));
    block_shift_y = __builtin_ctz(unsigned(bh));
    const TextureLayout layout = texture_layout(t, bw, bh);
    max_level = int(layout.first_line.size()) - 1;
    for (int i = 0; i <= max_level; ++i) {
      const MipLevel& l = t.levels[size_t(i)];
      const auto mask = [](int n) { return (n & (n - 1)) == 0 ? n - 1 : -1; };
      levels.push_back({l.width, l.height, mask(l.width), mask(l.height), layout.blocks_x[size_t(i)],
                        layout.first_line[size_t(i)], l.rgba.data()});
    }
  }
};

struct Rgba {
  float r = 0, g = 0, b = 0, a = 0;  // 0..255
};

// The four channels as one vector (GCC's and clang's vector extension:
// SSE on x86-64, NEON on arm64). Each lane does the scalar code's
// operations in the same order (no fused multiply-add: -ffp-contract=off),
// so the results are those of channel-by-channel float code, bit for bit.
using Float4 = float __attribute__((vector_size(16)));
using Byte4 = uint8_t __attribute__((vector_size(4)));

// An RGBA8 texel's channels as floats (exact: bytes are integers < 2^24).
[[gnu::always_inline]] inline Float4 texel4(const uint8_t* p) {
#if defined(__SSE2__)
  // One load and two unpacks: GCC expands the generic conversion below to
  // a byte extract and a scalar conversion per channel.
  int32_t word;
  std::memcpy(&word, p, 4);
  const __m128i zero = _mm_setzero_si128();
  const __m128i w = _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(word), zero), zero);
  return Float4(_mm_cvtepi32_ps(w));
#else
  Byte4 b;
  std::memcpy(&b, p, 4);
  return __builtin_convertvector(b, Float4);
#endif
}
inline Rgba to_rgba(Float4 v) { return {v[0], v[1], v[2], v[3]}; }
inline Float4 to_float4(const Rgba& c) { return Float4{c.r, c.g, c.b, c.a}; }
inline Float4 splat4(float x) { return Float4{x, x, x, x}; }
// std::clamp(x, lo, hi) in each lane (a NaN stays NaN, as std::clamp keeps it).
inline Float4 clamp4(Float4 x, float lo, float hi) {
  const Float4 l = splat4(lo), h = splat4(hi);
#if defined(__SSE2__)
  // maxps(a, b) is a > b ? a : b and minps(a, b) a < b ? a : b, to the bit
  // (a NaN or a tie of zeros gives b): x < l ? l : x, then h < y ? h : y.
  return Float4(_mm_min_ps(__m128(h), _mm_max_ps(__m128(l), __m128(x))));
#else
  return x < l ? l : (h < x ? h : x);
#endif
}

// A bilinear tap's weighted sum in each channel, ((w00 p00 + w10 p10) +
// w01 p01) + w11 p11, from its rows and columns: bilinear()'s and
// filter_tap()'s, so that the two give the same bits.
[[gnu::always_inline]] inline Float4 tap_sum(const uint8_t* row0, const uint8_t* row1, int i0, int i1, float w00, float w10,
                                             float w01, float w11) {
  return w00 * texel4(row0 + i0 * 4) + w10 * texel4(row0 + i1 * 4) + w01 * texel4(row1 + i0 * 4) + w11 * texel4(row1 + i1 * 4);
}

inline int wrap_coord(int i, int size, int mask, bool repeat) {
  if (repeat) {
    if (mask >= 0) return i & mask;  // two's complement: also right for negative i
    i %= size;
    return i < 0 ? i + size : i;
  }
  return i < 0 ? 0 : (i >= size ? size - 1 : i);
}

// The lines a bilinear tap's four texels lie in, given their blocks'
// columns (bx0, bx1) and rows (by0, by1), in the order the texels are read.
[[gnu::always_inline]] inline void add_tap_lines(const SamplerTexture& t, const LevelView& l, int bx0, int bx1, int by0, int by1,
                                                 QuadLines& lines) {
  const uint32_t base = l.first_line;
  lines.add(make_tex_line(t.id, base + uint32_t(by0 * l.blocks_x + bx0)));
  if (bx1 != bx0) lines.add(make_tex_line(t.id, base + uint32_t(by0 * l.blocks_x + bx1)));
  if (by1 != by0) {
    lines.add(make_tex_line(t.id, base + uint32_t(by1 * l.blocks_x + bx0)));
    if (bx1 != bx0) lines.add(make_tex_line(t.id, base + uint32_t(by1 * l.blocks_x + bx1)));
  }
}

// Coordinates far outside [0, 1] are clamped before they are converted, so
// as not to overflow int (repeat wraps modulo the size, which keeps them exact).
constexpr float kCoordLimit = 1 << 30;

// One point's bilinear tap of one level: its four texels' columns (i0, i1)
// and rows (j0, j1), wrapped, and the point's fractions (a, b) past the
// first (GL 4.5 equations 8.9-8.11). What bilinear() filters and
// bilinear_lines() records, so that the two read the same lines.
struct BilinearTap {
  int i0, i1, j0, j1;
  float a, b;
};

[[gnu::always_inline]] inline BilinearTap bilinear_tap(const SamplerTexture& t, const LevelView& l, float u, float v) {
  const float s = u * float(l.width) - 0.5f, tt = v * float(l.height) - 0.5f;
  const float fs = std::floor(s), ft = std::floor(tt);
  const int i0r = int(std::clamp(fs, -kCoordLimit, kCoordLimit)), j0r = int(std::clamp(ft, -kCoordLimit, kCoordLimit));
  return {wrap_coord(i0r, l.width, l.wrap_mask_x, t.repeat),
          wrap_coord(i0r + 1, l.width, l.wrap_mask_x, t.repeat),
          wrap_coord(j0r, l.height, l.wrap_mask_y, t.repeat),
          wrap_coord(j0r + 1, l.height, l.wrap_mask_y, t.repeat),
          s - fs,
          tt - ft};
}

// The lines a bilinear tap's texels lie in.
[[gnu::always_inline]] inline void add_bilinear_lines(const SamplerTexture& t, const LevelView& l, const BilinearTap& q,
                                                      QuadLines& lines) {
  add_tap_lines(t, l, q.i0 >> t.block_shift_x, q.i1 >> t.block_shift_x, q.j0 >> t.block_shift_y, q.j1 >> t.block_shift_y, lines);
}

// One point's bilinear sample of one level, the four channels at once.
[[gnu::always_inline]] inline Float4 bilinear(const SamplerTexture& t, int level, float u, float v, QuadLines* lines) {
  const LevelView& l = t.levels[size_t(level)];
  const BilinearTap q = bilinear_tap(t, l, u, v);
  const uint8_t* row0 = l.rgba + size_t(q.j0) * size_t(l.width) * 4;
  const uint8_t* row1 = l.rgba + size_t(q.j1) * size_t(l.width) * 4;
  const float a = q.a, b = q.b;
  const float w00 = (1 - a) * (1 - b), w10 = a * (1 - b), w01 = (1 - a) * b, w11 = a * b;
  const Float4 c = tap_sum(row0, row1, q.i0, q.i1, w00, w10, w01, w11);
  if (lines) add_bilinear_lines(t, l, q, *lines);
  return c;
}

// The levels a sample at level of detail `lambda` filters (GL 4.5 Section
// 8.14.2): magnification (lambda <= 0) filters level 0; minification blends
// the two nearest levels (GL_LINEAR_MIPMAP_LINEAR), the second with weight
// `f`, and fetches it only when that weight is not 0.
struct LevelChoice {
  int count = 1;
  int level[2] = {0, 0};
  float f = 0;
};

inline LevelChoice choose_levels(const SamplerTexture& t, float lambda) {
  LevelChoice c;
  if (!t.mipmapped || !(lambda > 0.0f)) return c;
  if (lambda >= float(t.max_level)) {
    c.level[0] = t.max_level;
    return c;
  }
  c.level[0] = int(lambda);
  c.f = lambda - float(c.level[0]);
  if (c.f != 0.0f) {
    c.count = 2;
    c.level[1] = c.level[0] + 1;
  }
  return c;
}

// Isotropic sample at level-of-detail `lambda`. `samples` counts bilinear
// lookups (a texture unit's unit of work).
inline Float4 sample_lod(const SamplerTexture& t, float u, float v, float lambda, QuadLines* lines, uint32_t& samples) {
  const LevelChoice c = choose_levels(t, lambda);
  samples += uint32_t(c.count);
  const Float4 c1 = bilinear(t, c.level[0], u, v, lines);
  if (c.count == 1) return c1;
  const Float4 c2 = bilinear(t, c.level[1], u, v, lines);
  return c1 + (c2 - c1) * c.f;
}

// floor() of four floats, exactly std::floor's results (signed zeros, NaN
// and infinities included).
inline Float4 floor4(Float4 x) {
#if defined(__SSE2__)
  // Truncate, step down where that rounded up, keep the sign of x (-0.0
  // stays -0.0, (-1, 0) gives -1); values of 2^23 or more, NaN and the
  // infinities are integers already, or stay what they are.
  const __m128 v = __m128(x);
  const __m128 sign = _mm_set1_ps(-0.0f);
  __m128 r = _mm_cvtepi32_ps(_mm_cvttps_epi32(v));
  r = _mm_sub_ps(r, _mm_and_ps(_mm_cmpgt_ps(r, v), _mm_set1_ps(1.0f)));
  r = _mm_or_ps(r, _mm_and_ps(v, sign));
  const __m128 small = _mm_cmplt_ps(_mm_andnot_ps(sign, v), _mm_set1_ps(8388608.0f));
  return Float4(_mm_or_ps(_mm_and_ps(small, r), _mm_andnot_ps(small, v)));
#else
  return Float4{std::floor(x[0]), std::floor(x[1]), std::floor(x[2]), std::floor(x[3])};
#endif
}

using Int4 = int32_t __attribute__((vector_size(16)));

// wrap_coord() in four lanes.
inline Int4 wrap4(Int4 i, int size, int mask, bool repeat) {
  if (repeat) {
    if (mask >= 0) return i & mask;
    return Int4{wrap_coord(i[0], size, mask, true), wrap_coord(i[1], size, mask, true), wrap_coord(i[2], size, mask, true),
                wrap_coord(i[3], size, mask, true)};
  }
  const Int4 zero{0, 0, 0, 0};
  const Int4 r = i < zero ? zero : i;
  return i >= size ? Int4{size - 1, size - 1, size - 1, size - 1} : r;
}

// int(std::clamp(x, -kCoordLimit, kCoordLimit)) in four lanes (a NaN
// converts as the scalar conversion does, to INT_MIN).
inline Int4 clamp_to_int4(Float4 x) {
  const Float4 c = clamp4(x, -kCoordLimit, kCoordLimit);
#if defined(__SSE2__)
  return Int4(_mm_cvttps_epi32(__m128(c)));
#else
  return __builtin_convertvector(c, Int4);
#endif
}

// One level's bilinear taps for a quad's four points, pixel p in lane p:
// bilinear()'s texel coordinates (wrapped), weights and line blocks.
struct QuadTaps {
  Int4 i0, i1, j0, j1;
  Float4 w00, w10, w01, w11;
  Int4 bx0, bx1, by0, by1;
};

// With `weights` false (the trace alone: lines, no filtering), the weights
// are left 0, not computed; the rest is the same arithmetic.
template <bool weights = true>
inline QuadTaps quad_taps(const SamplerTexture& t, const LevelView& l, Float4 u4, Float4 v4) {
  const Float4 s = u4 * float(l.width) - 0.5f, tt = v4 * float(l.height) - 0.5f;
  const Float4 fs = floor4(s), ft = floor4(tt);
  const Int4 i0r = clamp_to_int4(fs), j0r = clamp_to_int4(ft);
  QuadTaps q;
  q.i0 = wrap4(i0r, l.width, l.wrap_mask_x, t.repeat);
  q.i1 = wrap4(i0r + 1, l.width, l.wrap_mask_x, t.repeat);
  q.j0 = wrap4(j0r, l.height, l.wrap_mask_y, t.repeat);
  q.j1 = wrap4(j0r + 1, l.height, l.wrap_mask_y, t.repeat);
  if constexpr (weights) {
    const Float4 a = s - fs, b = tt - ft;
    q.w00 = (1 - a) * (1 - b);
    q.w10 = a * (1 - b);
    q.w01 = (1 - a) * b;
    q.w11 = a * b;
  } else {
    q.w00 = q.w10 = q.w01 = q.w11 = Float4{};
  }
  q.bx0 = q.i0 >> t.block_shift_x;
  q.bx1 = q.i1 >> t.block_shift_x;
  q.by0 = q.j0 >> t.block_shift_y;
  q.by1 = q.j1 >> t.block_shift_y;
  return q;
}

// bilinear()'s filtering for pixel p of a quad's taps: the same fetches, operations and
// lines in the same order.
[[gnu::always_inline]] inline Float4 filter_tap(const SamplerTexture& t, const LevelView& l, const QuadTaps& q, int p,
                                                QuadLines* lines) {
  const int i0 = q.i0[p], i1 = q.i1[p];
  const uint8_t* row0 = l.rgba + size_t(q.j0[p]) * size_t(l.width) * 4;
  const uint8_t* row1 = l.rgba + size_t(q.j1[p]) * size_t(l.width) * 4;
  const Float4 c = tap_sum(row0, row1, i0, i1, q.w00[p], q.w10[p], q.w01[p], q.w11[p]);
  if (lines) add_tap_lines(t, l, q.bx0[p], q.bx1[p], q.by0[p], q.by1[p], *lines);
  return c;
}

// A quad's four points sampled with one level of detail (a quad shares its
// footprint, so its levels too): the coordinate arithmetic of each level
// (texel coordinates, wrapping, weights, line blocks) in four lanes, then
// per live pixel, in pixel order, the fetches, filtering and lines of
// bilinear() for the first level and the second. Every lane does
// bilinear()'s operations in its order, so each `out[p]` and the lines
// recorded are those of sample_lod() pixel by pixel, bit for bit. `u4`,
// `v4` hold the pixels' coordinates in lanes 0..3 (the quad's order);
// `out[p]` the pixel's channels. Pixels not in `live` are not sampled
// (their coordinates may be anything, NaN included: a lane's conversion
// of one is defined, and its taps are not used).
inline void sample_quad(const SamplerTexture& t, Float4 u4, Float4 v4, float lambda, unsigned live, QuadLines* lines,
                        uint32_t& samples, Float4 out[4]) {
  const LevelChoice c = choose_levels(t, lambda);
  const LevelView& l0 = t.levels[size_t(c.level[0])];
  const QuadTaps q0 = quad_taps(t, l0, u4, v4);
  if (c.count == 1) {
    for (int p = 0; p < 4; ++p) {
      if (!(live & (1u << p))) continue;
      samples += 1;
      out[p] = filter_tap(t, l0, q0, p, lines);
    }
    return;
  }
  const LevelView& l1 = t.levels[size_t(c.level[1])];
  const QuadTaps q1 = quad_taps(t, l1, u4, v4);
  for (int p = 0; p < 4; ++p) {
    if (!(live & (1u << p))) continue;
    samples += 2;
    const Float4 r = filter_tap(t, l0, q0, p, lines);
    const Float4 r2 = filter_tap(t, l1, q1, p, lines);
    out[p] = r + (r2 - r) * c.f;
  }
}

// The trace without the image (PipelineSettings::draw_image off): the lines
// and bilinear lookups a sample records, without its texel fetches and
// filtering. Each does the coordinate arithmetic of the sampling function
// it stands for, in its order, so the lines are the same, bit for bit; a
// texel's value never decides which lines are read.

// bilinear()'s lines.
[[gnu::always_inline]] inline void bilinear_lines(const SamplerTexture& t, int level, float u, float v, QuadLines* lines) {
  const LevelView& l = t.levels[size_t(level)];
  add_bilinear_lines(t, l, bilinear_tap(t, l, u, v), *lines);
}

// sample_lod()'s lines and lookups.
inline void sample_lod_lines(const SamplerTexture& t, float u, float v, float lambda, QuadLines* lines, uint32_t& samples) {
  const LevelChoice c = choose_levels(t, lambda);
  samples += uint32_t(c.count);
  if (!lines) return;
  bilinear_lines(t, c.level[0], u, v, lines);
  if (c.count == 2) bilinear_lines(t, c.level[1], u, v, lines);
}

// sample_quad()'s taps for a quad's lines: its levels and, per level, each
// pixel's texel blocks, from sample_quad()'s arithmetic lane for lane.
struct QuadLinePlan {
  LevelChoice c;
  QuadTaps q[2];
};

inline void plan_quad_lines(const SamplerTexture& t, Float4 u4, Float4 v4, float lambda, QuadLinePlan& plan) {
  plan.c = choose_levels(t, lambda);
  for (int i = 0; i < plan.c.count; ++i) plan.q[i] = quad_taps<false>(t, t.levels[size_t(plan.c.level[i])], u4, v4);
}

// Whether every live pixel's tap of `q` reads one texel block, the same for
// all (its four texels' columns and rows in the first live pixel's block).
inline bool one_block(const QuadTaps& q, unsigned live) {
  const int p = __builtin_ctz(live);
  const Int4 x = Int4{} + q.bx0[p], y = Int4{} + q.by0[p];
  const Int4 same = (q.bx0 == x) & (q.bx1 == x) & (q.by0 == y) & (q.by1 == y);
#if defined(__SSE2__)
  const unsigned bits = unsigned(_mm_movemask_ps(_mm_castsi128_ps(__m128i(same))));
#else
  unsigned bits = 0;
  for (int k = 0; k < 4; ++k) bits |= unsigned(same[k] & 1) << k;
#endif
  return (bits & live) == live;
}

// The lines and lookups of a plan, for texture `t` (the plan's, or one of
// the same shape: SamplerTexture::shape), in pixel order, the first level's
// before the second's, as sample_quad() records them.
[[gnu::always_inline]] inline void add_quad_lines(const SamplerTexture& t, const QuadLinePlan& plan, unsigned live,
                                                  QuadLines* lines, uint32_t& samples) {
  samples += uint32_t(plan.c.count) * pixels_in(live);
  if (!lines || !(live & 0xfu)) return;
  const LevelView& l0 = t.levels[size_t(plan.c.level[0])];
  const QuadTaps& q0 = plan.q[0];
  // Many quads (about half of oa:oa_dm4's at 1280x1024) read one block of
  // each level: its line is all the pixels add, the first pixel's first and
  // the others' repeats, so the first pixel's lines are the quad's (in its
  // order: the first level's, then the second's).
  if (one_block(q0, live) && (plan.c.count == 1 || one_block(plan.q[1], live))) {
    const int p = __builtin_ctz(live);
    add_tap_lines(t, l0, q0.bx0[p], q0.bx1[p], q0.by0[p], q0.by1[p], *lines);
    if (plan.c.count == 2) {
      const LevelView& l1 = t.levels[size_t(plan.c.level[1])];
      const QuadTaps& q1 = plan.q[1];
      add_tap_lines(t, l1, q1.bx0[p], q1.bx1[p], q1.by0[p], q1.by1[p], *lines);
    }
    return;
  }
  // The live pixels in ascending order, one step each (a test of every
  // pixel's bit would mispredict on quads that triangles' edges cut).
  if (plan.c.count == 1) {
    for (unsigned m = live & 0xfu; m; m &= m - 1) {
      const int p = __builtin_ctz(m);
      add_tap_lines(t, l0, q0.bx0[p], q0.bx1[p], q0.by0[p], q0.by1[p], *lines);
    }
    return;
  }
  const LevelView& l1 = t.levels[size_t(plan.c.level[1])];
  const QuadTaps& q1 = plan.q[1];
  for (unsigned m = live & 0xfu; m; m &= m - 1) {
    const int p = __builtin_ctz(m);
    add_tap_lines(t, l0, q0.bx0[p], q0.bx1[p], q0.by0[p], q0.by1[p], *lines);
    add_tap_lines(t, l1, q1.bx0[p], q1.bx1[p], q1.by0[p], q1.by1[p], *lines);
  }
}

// sample_quad()'s lines and lookups: the same blocks from the same taps.
inline void sample_quad_lines(const SamplerTexture& t, Float4 u4, Float4 v4, float lambda, unsigned live, QuadLines* lines,
                              uint32_t& samples) {
  QuadLinePlan plan;
  plan_quad_lines(t, u4, v4, lambda, plan);
  add_quad_lines(t, plan, live, lines, samples);
}

// Texture-space derivatives of one quad, in texels of level 0.
struct Derivs {
  float dudx, dvdx, dudy, dvdy;  // in [0,1] texture units per pixel
};

// How a quad samples a texture, from its derivatives: the level of detail
// and, with anisotropic filtering, the probes along the major axis of the
// pixel footprint (EXT_texture_filter_anisotropic's reference
// formulation). The same for the quad's four pixels, so computed once.
struct Footprint {
  float lambda = -1.0f;
  int probes = 1;        // 1: one isotropic sample
  float du = 0, dv = 0;  // the major axis, in texture units (probes > 1)
};

// A level of detail that choose_levels() turns into the levels, and their
// count, that std::log2(x) would give, without the logarithm where x's
// exponent decides them; not log2(x) itself (the second level's weight
// differs), so only for the trace alone, which records lines and counts
// lookups but never filters. A normal x = 2^e (1 + m) with m in [2^-12,
// 1 - 2^-12] has log2(x) in (e, e + 1), at least 3.5e-4 from both ends;
// glibc's log2f is within an ulp (at most 2^-16 where |log2(x)| < 128), so
// it too lies strictly between e and e + 1 (checked for every one of the
// 2,129,666,302 floats in that range), as e + 0.5 does: on the same side of
// 0 and of every level, with the same integer part and a fraction that is
// not 0. Anything else (near a power of two, zero, subnormal, negative,
// infinite, NaN) takes std::log2. log2f was 3% of the trace pass's
// instructions (docs/performance.md, "The trace pass without `log2f`, ...").
inline float lod_for_levels(float x) {
  uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const uint32_t exponent = bits >> 23;  // with the sign bit: a negative x is out of range
  const uint32_t mantissa = bits & 0x7fffffu;
  if (exponent - 1u < 254u && mantissa - (1u << 11) <= (1u << 23) - (1u << 12)) return float(int(exponent) - 127) + 0.5f;
  return std::log2(x);
}

// With `levels_only`, the footprint's `lambda` is lod_for_levels()'s: the
// same levels as the footprint's own level of detail, for the trace alone.
template <bool levels_only = false>
inline Footprint footprint(const SamplerTexture& t, const Derivs& d, int max_aniso) {
  // A texture without mipmaps (a lightmap) is sampled at level 0 whatever
  // the level of detail (choose_levels), by one isotropic probe: nothing to
  // compute. Half the layers of a lit game level's surfaces are lightmaps.
  if (!t.mipmapped) return Footprint{};
  const auto lod = [](float x) {
    if constexpr (levels_only) return lod_for_levels(x);
    else return std::log2(x);
  };
  const float w0 = float(t.levels[0].width), h0 = float(t.levels[0].height);
  const float px = std::sqrt((d.dudx * w0) * (d.dudx * w0) + (d.dvdx * h0) * (d.dvdx * h0));
  const float py = std::sqrt((d.dudy * w0) * (d.dudy * w0) + (d.dvdy * h0) * (d.dvdy * h0));
  const float pmax = std::max(px, py);
  Footprint f;
  if (max_aniso <= 1) {
    f.lambda = pmax > 0 ? lod(pmax) : -1.0f;
    return f;
  }
  const float pmin = std::min(px, py);
  const float ratio = pmin > 0 ? pmax / pmin : float(max_aniso);
  // ceil(ratio) capped at max_aniso before it is converted: a ratio past
  // INT_MAX (a footprint all but a line) does not convert (x86 made it
  // INT_MIN, one probe). A NaN ratio takes one probe.
  f.probes = ratio >= float(max_aniso) ? max_aniso : ratio > 1.0f ? int(std::ceil(ratio)) : 1;
  f.lambda = pmax > 0 ? lod(pmax / float(f.probes)) : -1.0f;
  f.du = px >= py ? d.dudx : d.dudy;
  f.dv = px >= py ? d.dvdx : d.dvdy;
  return f;
}

// Probe i of n's offset along the major axis, in units of the axis.
inline float probe_offset(int i, int n) { return (float(i) + 0.5f) / float(n) - 0.5f; }

// One pixel's sample with its quad's footprint: an isotropic sample, or the
// mean of the probes along the major axis.
inline Rgba sample(const SamplerTexture& t, float u, float v, const Footprint& f, QuadLines* lines, uint32_t& samples) {
  if (f.probes == 1) return to_rgba(sample_lod(t, u, v, f.lambda, lines, samples));
  const int n = f.probes;
  Float4 acc{0, 0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const float o = probe_offset(i, n);
    acc += sample_lod(t, u + f.du * o, v + f.dv * o, f.lambda, lines, samples);
  }
  const float inv = 1.0f / float(n);
  return to_rgba(acc * inv);
}

// sample()'s lines and lookups: each probe's, in order.
inline void sample_lines(const SamplerTexture& t, float u, float v, const Footprint& f, QuadLines* lines, uint32_t& samples) {
  if (f.probes == 1) return sample_lod_lines(t, u, v, f.lambda, lines, samples);
  const int n = f.probes;
  for (int i = 0; i < n; ++i) {
    const float o = probe_offset(i, n);
    sample_lod_lines(t, u + f.du * o, v + f.dv * o, f.lambda, lines, samples);
  }
}

}  // namespace oovr::detail
