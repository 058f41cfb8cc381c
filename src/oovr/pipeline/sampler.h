// Texture sampling as OpenGL 4.5 (Section 8.14) specifies it for
// GL_LINEAR_MIPMAP_LINEAR minification and GL_LINEAR magnification, with
// optional anisotropic filtering (EXT_texture_filter_anisotropic), recording
// the cache lines each fetch touches. Internal to the pipeline.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

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
  }
  void add(TexLine l) {
    if (l == m_last) return;  // most repeats are of the line just added
    m_last = l;
    for (int i = 0; i < m_count; ++i)
      if (m_lines[i] == l) return;
    if (m_count < kMax) {
      m_lines[m_count++] = l;
    } else {
      m_overflow.push_back(l);  // rare: huge footprints (extreme anisotropy)
    }
  }
  template <class Out>
  void flush(Out& out) {
    out.insert(out.end(), m_lines, m_lines + m_count);
    if (!m_overflow.empty()) {
      std::sort(m_overflow.begin(), m_overflow.end());
      m_overflow.erase(std::unique(m_overflow.begin(), m_overflow.end()), m_overflow.end());
      for (TexLine l : m_overflow)
        if (std::find(m_lines, m_lines + m_count, l) == m_lines + m_count) out.push_back(l);
      m_overflow.clear();
    }
    clear();
  }

 private:
  static constexpr int kMax = 64;
  TexLine m_lines[kMax];
  int m_count = 0;
  TexLine m_last = ~TexLine(0);
  std::vector<TexLine> m_overflow;
};

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

inline int wrap_coord(int i, int size, int mask, bool repeat) {
  if (repeat) {
    if (mask >= 0) return i & mask;  // two's complement: also right for negative i
    i %= size;
    return i < 0 ? i + size : i;
  }
  return i < 0 ? 0 : (i >= size ? size - 1 : i);
}

// Bilinear filtering of one level (GL 4.5 equations 8.9-8.11).
[[gnu::always_inline]] inline Rgba bilinear(const SamplerTexture& t, int level, float u, float v, QuadLines* lines) {
  const LevelView& l = t.levels[size_t(level)];
  const float s = u * float(l.width) - 0.5f, tt = v * float(l.height) - 0.5f;
  const float fs = std::floor(s), ft = std::floor(tt);
  const float a = s - fs, b = tt - ft;
  // Clamp before converting: coordinates far outside [0, 1] must not
  // overflow int (repeat wraps modulo the size, which keeps them exact).
  const float lim = 1 << 30;
  const int i0r = int(std::clamp(fs, -lim, lim)), j0r = int(std::clamp(ft, -lim, lim));
  const int i0 = wrap_coord(i0r, l.width, l.wrap_mask_x, t.repeat);
  const int i1 = wrap_coord(i0r + 1, l.width, l.wrap_mask_x, t.repeat);
  const int j0 = wrap_coord(j0r, l.height, l.wrap_mask_y, t.repeat);
  const int j1 = wrap_coord(j0r + 1, l.height, l.wrap_mask_y, t.repeat);
  const uint8_t* p00 = l.rgba + (size_t(j0) * l.width + i0) * 4;
  const uint8_t* p10 = l.rgba + (size_t(j0) * l.width + i1) * 4;
  const uint8_t* p01 = l.rgba + (size_t(j1) * l.width + i0) * 4;
  const uint8_t* p11 = l.rgba + (size_t(j1) * l.width + i1) * 4;
  const float w00 = (1 - a) * (1 - b), w10 = a * (1 - b), w01 = (1 - a) * b, w11 = a * b;
  Rgba c;
  c.r = w00 * p00[0] + w10 * p10[0] + w01 * p01[0] + w11 * p11[0];
  c.g = w00 * p00[1] + w10 * p10[1] + w01 * p01[1] + w11 * p11[1];
  c.b = w00 * p00[2] + w10 * p10[2] + w01 * p01[2] + w11 * p11[2];
  c.a = w00 * p00[3] + w10 * p10[3] + w01 * p01[3] + w11 * p11[3];
  if (lines) {
    const uint32_t base = l.first_line;
    const int bx0 = i0 >> t.block_shift_x, bx1 = i1 >> t.block_shift_x;
    const int by0 = j0 >> t.block_shift_y, by1 = j1 >> t.block_shift_y;
    lines->add(make_tex_line(t.id, base + uint32_t(by0 * l.blocks_x + bx0)));
    if (bx1 != bx0) lines->add(make_tex_line(t.id, base + uint32_t(by0 * l.blocks_x + bx1)));
    if (by1 != by0) {
      lines->add(make_tex_line(t.id, base + uint32_t(by1 * l.blocks_x + bx0)));
      if (bx1 != bx0) lines->add(make_tex_line(t.id, base + uint32_t(by1 * l.blocks_x + bx1)));
    }
  }
  return c;
}

inline Rgba mix(const Rgba& x, const Rgba& y, float f) {
  return {x.r + (y.r - x.r) * f, x.g + (y.g - x.g) * f, x.b + (y.b - x.b) * f, x.a + (y.a - x.a) * f};
}

// Isotropic sample at level-of-detail `lambda` (GL 4.5 Section 8.14.2):
// magnification (lambda <= 0) filters level 0; minification blends the two
// nearest levels (GL_LINEAR_MIPMAP_LINEAR).
// `samples` counts bilinear lookups (a texture unit's unit of work).
inline Rgba sample_lod(const SamplerTexture& t, float u, float v, float lambda, QuadLines* lines, uint32_t& samples) {
  ++samples;
  if (!t.mipmapped || !(lambda > 0.0f)) return bilinear(t, 0, u, v, lines);
  if (lambda >= float(t.max_level)) return bilinear(t, t.max_level, u, v, lines);
  const int d1 = int(lambda);
  const float f = lambda - float(d1);
  const Rgba c1 = bilinear(t, d1, u, v, lines);
  if (f == 0.0f) return c1;  // the second level has no weight: not fetched
  ++samples;
  const Rgba c2 = bilinear(t, d1 + 1, u, v, lines);
  return mix(c1, c2, f);
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

inline Footprint footprint(const SamplerTexture& t, const Derivs& d, int max_aniso) {
  const float w0 = float(t.levels[0].width), h0 = float(t.levels[0].height);
  const float px = std::sqrt((d.dudx * w0) * (d.dudx * w0) + (d.dvdx * h0) * (d.dvdx * h0));
  const float py = std::sqrt((d.dudy * w0) * (d.dudy * w0) + (d.dvdy * h0) * (d.dvdy * h0));
  const float pmax = std::max(px, py);
  Footprint f;
  if (max_aniso <= 1 || !t.mipmapped) {
    f.lambda = pmax > 0 ? std::log2(pmax) : -1.0f;
    return f;
  }
  const float pmin = std::min(px, py);
  const float ratio = pmin > 0 ? pmax / pmin : float(max_aniso);
  f.probes = std::clamp(int(std::ceil(ratio)), 1, max_aniso);
  f.lambda = pmax > 0 ? std::log2(pmax / float(f.probes)) : -1.0f;
  f.du = px >= py ? d.dudx : d.dudy;
  f.dv = px >= py ? d.dvdx : d.dvdy;
  return f;
}

// One pixel's sample with its quad's footprint: an isotropic sample, or the
// mean of the probes along the major axis.
inline Rgba sample(const SamplerTexture& t, float u, float v, const Footprint& f, QuadLines* lines, uint32_t& samples) {
  if (f.probes == 1) return sample_lod(t, u, v, f.lambda, lines, samples);
  const int n = f.probes;
  Rgba acc;
  for (int i = 0; i < n; ++i) {
    const float o = (float(i) + 0.5f) / float(n) - 0.5f;
    const Rgba c = sample_lod(t, u + f.du * o, v + f.dv * o, f.lambda, lines, samples);
    acc.r += c.r;
    acc.g += c.g;
    acc.b += c.b;
    acc.a += c.a;
  }
  const float inv = 1.0f / float(n);
  return {acc.r * inv, acc.g * inv, acc.b * inv, acc.a * inv};
}

}  // namespace oovr::detail
