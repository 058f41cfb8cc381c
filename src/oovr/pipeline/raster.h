// The functional pipeline's rasteriser (renderer.cpp's, included only
// there and by its tests): a tile's bin of set-up triangles rasterised in draw order, each
// fragment shaded from its pass's layers, tested, blended and written, and
// the tile's part of the trace recorded (llvmpipe's rast module; STYLE.md).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "oovr/core/error.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/sampler.h"
#include "oovr/pipeline/setup.h"
#include "oovr/pipeline/shader_cost.h"

namespace oovr::detail {

// A texture layer ready to sample in this frame.
struct PreparedLayer {
  const detail::SamplerTexture* texture;
  bool lightmap_coords;
  bool transformed;
  UvTransform xf;
  Combine combine;
  float scale;
};

// An object's pass ready to draw in this frame.
struct PreparedPass {
  const Pass* pass;
  std::vector<PreparedLayer> layers;
  bool lightmap_coords = false;  // some layer samples with lightmap coordinates
  bool coloured = false;         // vertex colours multiply the pass (uses_vertex_colours)
  bool replace = false;          // the first layer's texel is the colour (Combine::replace)
  // Shading::deluxe: which layer holds what (-1: none).
  int diffuse = -1, normal = -1, gloss = -1, glow = -1, lightmap = -1, deluxe = -1;
};

// Shading::deluxe for one fragment (scene/material.h gives the formula;
// DarkPlaces' MODE_LIGHTDIRECTIONMAP_MODELSPACE). Texels are 0..255; `lit`
// the interpolated S, T, N and eye vector.
inline detail::Rgba shade_deluxe(const PreparedPass& pp, const detail::Rgba* texel, const float* lit) {
  const Pass& pass = *pp.pass;
  const detail::Rgba& d = texel[pp.diffuse];
  const detail::Rgba& lm = texel[pp.lightmap];
  const detail::Rgba& dx = texel[pp.deluxe];
  const float lm_scale = pp.layers[size_t(pp.lightmap)].scale;
  const Vec3 S{lit[0], lit[1], lit[2]}, T{lit[3], lit[4], lit[5]}, N{lit[6], lit[7], lit[8]};
  const Vec3 E{lit[9], lit[10], lit[11]};
  const Vec3 lm_dir{dx.r / 255.0f * 2.0f - 1.0f, dx.g / 255.0f * 2.0f - 1.0f, dx.b / 255.0f * 2.0f - 1.0f};
  const Vec3 l = normalize(Vec3{dot(lm_dir, S), dot(lm_dir, T), dot(lm_dir, N)});
  const float k = lm_scale / std::max(0.25f, l.z) / 255.0f;
  const Vec3 lc{lm.r * k, lm.g * k, lm.b * k};
  Vec3 n{0, 0, 1};
  if (pp.normal >= 0) {
    const detail::Rgba& t = texel[pp.normal];
    n = normalize(Vec3{t.r / 255.0f - 0.5f, t.g / 255.0f - 0.5f, t.b / 255.0f - 0.5f});
  }
  const float diffuse = std::max(dot(n, l), 0.0f);
  detail::Rgba c{d.r * diffuse * lc.x, d.g * diffuse * lc.y, d.b * diffuse * lc.z, d.a};
  if (pp.gloss >= 0) {
    const detail::Rgba& g = texel[pp.gloss];
    const Vec3 h = normalize(l + normalize(E));
    const float nh = std::max(dot(n, h), 0.0f);
    // pow(0, y) is left undefined by GLSL; both renderers call it 0.
    const float spec = nh > 0.0f ? std::pow(nh, pass.specular_power * (g.a / 255.0f)) : 0.0f;
    const float gk = pass.specular_intensity * spec;
    c.r += g.r * gk * lc.x;
    c.g += g.g * gk * lc.y;
    c.b += g.b * gk * lc.z;
  }
  if (pp.glow >= 0) {
    const detail::Rgba& g = texel[pp.glow];
    c.r += g.r;
    c.g += g.g;
    c.b += g.b;
  }
  c.r *= pass.colour.x;
  c.g *= pass.colour.y;
  c.b *= pass.colour.z;
  c.a *= pass.colour.w;
  return c;
}

// A per-pixel lit pass samples at most this many layers (diffuse, normal,
// gloss, glow, lightmap, deluxe and room for two more).
constexpr size_t kMaxDeluxeLayers = 8;

// Whether two vectors hold the same bits (NaNs and signed zeros told apart).
inline bool same_bits(Float4 a, Float4 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline bool depth_passes(DepthFunc f, float z, float stored) {
  switch (f) {
    case DepthFunc::less: return z < stored;
    case DepthFunc::lequal: return z <= stored;
    case DepthFunc::equal: return z == stored;
    case DepthFunc::always: return true;
  }
  return false;
}

inline bool alpha_passes(AlphaFunc f, float a, float ref255) {
  switch (f) {
    case AlphaFunc::always: return true;
    case AlphaFunc::greater: return a > ref255;
    case AlphaFunc::less: return a < ref255;
    case AlphaFunc::gequal: return a >= ref255;
  }
  return false;
}

// A blend factor (0..1) per channel: s and d are the source and
// destination colours (0..255) as channel vectors; each lane computes what
// the channel's scalar factor would.
inline Float4 blend_factor(BlendFactor f, Float4 s, Float4 d) {
  switch (f) {
    case BlendFactor::zero: return splat4(0.0f);
    case BlendFactor::one: return splat4(1.0f);
    case BlendFactor::src_colour: return s / 255.0f;
    case BlendFactor::one_minus_src_colour: return 1.0f - s / 255.0f;
    case BlendFactor::src_alpha: return splat4(s[3] / 255.0f);
    case BlendFactor::one_minus_src_alpha: return splat4(1.0f - s[3] / 255.0f);
    case BlendFactor::dst_colour: return d / 255.0f;
    case BlendFactor::one_minus_dst_colour: return 1.0f - d / 255.0f;
    case BlendFactor::dst_alpha: return splat4(d[3] / 255.0f);
    case BlendFactor::one_minus_dst_alpha: return splat4(1.0f - d[3] / 255.0f);
  }
  return splat4(0.0f);
}

// Whether this CPU has fused multiply-add instructions (x86-64's FMA3).
inline bool cpu_has_fma() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool has = __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

// A quad's depths at its four pixel centres (x, y), clamped to [0, 1] as
// std::max(std::min(z, 1), 0) does (NaN kept), from the plane's
// fma(dzdy, y, fma(dzdx, x, z0)) in `zp`.
[[gnu::always_inline]] inline Float4 clamp_depth(Float4 zp) {
  const Float4 one = splat4(1.0f), zero = splat4(0.0f);
  const Float4 m = one < zp ? one : zp;
  return m < zero ? zero : m;
}

// A quad's pixel centres' coordinates, pixel p in lane p. float(q + 1) is
// float(q) + 1 exactly: pixel coordinates are at most 16384 (a frame's
// side, scene/stereo.cpp), far below 2^24.
[[gnu::always_inline]] inline void quad_xy(int qx, int qy, Float4& x, Float4& y) {
  x = splat4(float(qx)) + Float4{0, 1, 0, 1};
  y = splat4(float(qy)) + Float4{0, 0, 1, 1};
}

#if defined(__x86_64__) && defined(__GNUC__)
// plane_depth() by the FMA3 instruction, four lanes at a time: one rounding,
// as std::fma, so the same bits; the whole quad in one call (a function of
// another target is not inlined). Called only where cpu_has_fma().
[[gnu::target("fma")]] inline Float4 plane_depth_fma(const SetupTri& t, int qx, int qy) {
  Float4 x, y;
  quad_xy(qx, qy, x, y);
  const __m128 inner = _mm_fmadd_ps(__m128(splat4(t.dzdx)), __m128(x), __m128(splat4(t.z0)));
  return clamp_depth(Float4(_mm_fmadd_ps(__m128(splat4(t.dzdy)), __m128(y), inner)));
}
#endif

// A quad's depths: fma(dzdy, y, fma(dzdx, x, z0)) at its four pixel
// centres, clamped to [0, 1]. With `use_fma`, by the instruction four lanes
// at a time; else by std::fma pixel by pixel (a library call without the
// instruction). The same bits either way: fma rounds once.
inline Float4 plane_depth(const SetupTri& t, int qx, int qy, bool use_fma) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (use_fma) return plane_depth_fma(t, qx, qy);
#endif
  (void)use_fma;
  Float4 x, y, zp;
  quad_xy(qx, qy, x, y);
  for (int p = 0; p < 4; ++p) zp[p] = std::fma(t.dzdy, y[p], std::fma(t.dzdx, x[p], t.z0));
  return clamp_depth(zp);
}

// Per-tile rasterisation and shading. A tile is drawn in buffers of its own
// (as llvmpipe keeps a tile in cache), cleared when it starts and copied
// into the frame when it ends: its colour, depth and object ids stay in the
// core's first-level cache, and two threads drawing neighbouring tiles never
// write the same host cache line. Writes only the tile's own pixels.
class TileRasterizer {
 public:
  // The frame a tile is copied into: its colour (RGBA8) and object ids, row
  // by row, `width` x `height` pixels.
  struct Frame {
    uint8_t* colour;
    uint32_t* ids;
    int width, height;
  };

  TileRasterizer(const std::vector<SetupTri>& tris, const std::vector<LitTri>& lit, const std::vector<PreparedPass>& passes,
                 const PipelineSettings& settings, int block_w, int block_h, Frame frame)
      : m_tris(tris),
        m_lit(lit),
        m_passes(passes),
        m_settings(settings),
        m_block_shift_x(__builtin_ctz(unsigned(block_w))),
        m_block_shift_y(__builtin_ctz(unsigned(block_h))),
        m_frame(frame),
        m_image(settings.draw_image),
        m_fma(cpu_has_fma()) {
    // Framebuffer blocks are powers of two of at least 4x2 pixels
    // (line_block_shape, lines of 32 bytes or more): a 2x2 quad at even
    // coordinates lies in one line.
    if (block_w < 2 || block_h < 2 || (block_w & (block_w - 1)) || (block_h & (block_h - 1)) || block_w > kTileSize ||
        block_h > kTileSize)
      throw Error("framebuffer line blocks must be powers of two from 2 to " + std::to_string(kTileSize) + " pixels a side");
  }

  struct Output {
    std::vector<TileWork> work;
    std::vector<TexLine> lines;
  };

  // Draws tile (tx, ty) from its bin (empty or not: the tile's pixels are
  // cleared either way) into the frame, and its records and lines into `out`.
  void run(int tx, int ty, const std::vector<uint32_t>& bin, Output& out) {
    m_tx = tx;
    m_ty = ty;
    m_out = &out;
    m_open = false;
    // The frame's clear values: opaque black, the far plane, no object.
    for (int i = 0; i < kTilePixels; ++i) m_depth[i] = 1.0f;
    if (m_image) {
      for (int i = 0; i < kTilePixels; ++i) {
        m_colour[i * 4 + 0] = m_colour[i * 4 + 1] = m_colour[i * 4 + 2] = 0;
        m_colour[i * 4 + 3] = 255;
        m_ids[i] = kNoObject;
      }
    }
    draw(bin);
    if (!m_image) return;
    const int x0 = tx * kTileSize, y0 = ty * kTileSize;
    const int w = std::min(kTileSize, m_frame.width - x0), h = std::min(kTileSize, m_frame.height - y0);
    for (int ly = 0; ly < h; ++ly) {
      const size_t row = size_t(y0 + ly) * size_t(m_frame.width) + size_t(x0);
      std::memcpy(m_frame.colour + row * 4, m_colour + ly * kTileSize * 4, size_t(w) * 4);
      std::memcpy(m_frame.ids + row, m_ids + ly * kTileSize, size_t(w) * sizeof(uint32_t));
    }
  }

 private:
  void draw(const std::vector<uint32_t>& bin) {
    for (uint32_t id : bin) {
      const SetupTri& t = m_tris[id];
      if (!m_open || t.object != m_cur.object || t.eye != m_cur.eye) {
        close();
        open(t);
      }
      ++m_cur.triangles;
      m_vids.insert(m_vids.end(), t.vid, t.vid + 3);
      raster(t);
    }
    close();
  }

  void open(const SetupTri& t) {
    m_cur = TileWork{};
    m_cur.object = t.object;
    m_cur.eye = uint16_t(t.eye);
    m_cur.tile_x = uint16_t(m_tx);
    m_cur.tile_y = uint16_t(m_ty);
    m_cur.tex_begin = m_out->lines.size();
    m_vids.clear();
    m_open = true;
  }

  void close() {
    if (!m_open) return;
    std::sort(m_vids.begin(), m_vids.end());
    m_cur.vertices = uint32_t(std::unique(m_vids.begin(), m_vids.end()) - m_vids.begin());
    m_cur.tex_count = uint32_t(m_out->lines.size() - m_cur.tex_begin);
    m_out->work.push_back(m_cur);
    m_open = false;
  }

  // Pixel (x, y)'s index in the tile's buffers.
  size_t in_tile(int x, int y) const { return size_t((y - m_ty * kTileSize) * kTileSize + (x - m_tx * kTileSize)); }

  // The framebuffer line (within the tile) that holds pixel (x, y), and
  // every pixel of its quad: line_row(y) + line_column(x).
  uint32_t line_row(int y) const {
    return uint32_t(((y - m_ty * kTileSize) >> m_block_shift_y) << (kTileShift - m_block_shift_x));
  }
  uint32_t line_column(int x) const { return uint32_t((x - m_tx * kTileSize) >> m_block_shift_x); }

  // Triangle t's three edge values at the quad's four pixels (pixel p of
  // edge i in e[i][p], as base + {0, a, b, a + b} from base = a qx + b qy
  // + c), and the pixels inside all three (bit p): a pixel is out where
  // e + bias < 0, its sign bit, taken without a branch (edge pixels would
  // mispredict one). Integer arithmetic, so lanes give the scalar values.
  // `row` holds b qy + c per edge (the quad row's part).
  static unsigned edge_values(const SetupTri& t, int qx, const int64_t row[3], int64_t e[3][4]) {
    unsigned out = 0;
    for (int i = 0; i < 3; ++i) {
      const int64_t base = t.a[i] * qx + row[i];
#if defined(__SSE2__)
      // Two pixels to a register; the sign bits of e + bias by one movmskpd.
      const __m128i b = _mm_set1_epi64x(base), bias = _mm_set1_epi64x(t.bias[i]);
      const __m128i e01 = _mm_add_epi64(b, _mm_set_epi64x(t.a[i], 0));
      const __m128i e23 = _mm_add_epi64(b, _mm_set_epi64x(t.a[i] + t.b[i], t.b[i]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(&e[i][0]), e01);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(&e[i][2]), e23);
      out |= unsigned(_mm_movemask_pd(_mm_castsi128_pd(_mm_add_epi64(e01, bias)))) |
             unsigned(_mm_movemask_pd(_mm_castsi128_pd(_mm_add_epi64(e23, bias)))) << 2;
#else
      e[i][0] = base;
      e[i][1] = base + t.a[i];
      e[i][2] = base + t.b[i];
      e[i][3] = base + t.a[i] + t.b[i];
      for (int p = 0; p < 4; ++p) out |= unsigned(uint64_t(e[i][p] + t.bias[i]) >> 63) << p;
#endif
    }
    return ~out & 0xfu;
  }

#if defined(__SSE2__)
  // Whether every edge value of t at pixels x in [xa, xb], y in [ya, yb]
  // lies within +-2^30 (at the rectangle's corners, the values being
  // linear): then it, its sum with the bias and the quad's offsets {0, a,
  // b, a + b} are 32-bit integers, and edge_values32() gives the values
  // edge_values() does.
  static bool edges_fit_32(const SetupTri& t, int xa, int ya, int xb, int yb) {
    constexpr int64_t kLimit = int64_t(1) << 30;
    for (int i = 0; i < 3; ++i)
      for (const int64_t x : {xa, xb})
        for (const int64_t y : {ya, yb}) {
          const int64_t v = t.a[i] * x + t.b[i] * y + t.c[i];
          if (v >= kLimit || v <= -kLimit) return false;
        }
    return true;
  }

  // edge_values() where edges_fit_32(): the four pixels of an edge in one
  // register of 32-bit lanes (`offsets[i]` = {0, a, b, a + b}, `bias[i]`
  // its bias in each lane), their sign bits by one movmskps.
  static unsigned edge_values32(const SetupTri& t, int qx, const int64_t row[3], const __m128i offsets[3], const __m128i bias[3],
                                __m128i e[3]) {
    unsigned out = 0;
    for (int i = 0; i < 3; ++i) {
      e[i] = _mm_add_epi32(_mm_set1_epi32(int32_t(t.a[i] * qx + row[i])), offsets[i]);
      out |= unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_add_epi32(e[i], bias[i]))));
    }
    return ~out & 0xfu;
  }
#endif

  // Which of a quad's four depths pass `f` against the stored ones `stored`
  // (bit p for pixel p), each compared as depth_passes() compares it (a
  // NaN passes nothing but `always`).
  static unsigned depths_passing(DepthFunc f, Float4 z, Float4 stored) {
#if defined(__SSE2__)
    const __m128 a = __m128(z), b = __m128(stored);
    switch (f) {
      case DepthFunc::less: return unsigned(_mm_movemask_ps(_mm_cmplt_ps(a, b)));
      case DepthFunc::lequal: return unsigned(_mm_movemask_ps(_mm_cmple_ps(a, b)));
      case DepthFunc::equal: return unsigned(_mm_movemask_ps(_mm_cmpeq_ps(a, b)));
      case DepthFunc::always: return 0xfu;
    }
    return 0;
#else
    unsigned out = 0;
    for (int p = 0; p < 4; ++p) out |= unsigned(depth_passes(f, z[p], stored[p])) << p;
    return out;
#endif
  }

  // The tile's stored depths at a quad's four pixels, from pixel 0's index:
  // two pairs of neighbours in a row.
  Float4 quad_depths(size_t pix) const {
#if defined(__SSE2__)
    const __m128 top = _mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(m_depth + pix));
    return Float4(_mm_loadh_pi(top, reinterpret_cast<const __m64*>(m_depth + pix + kTileSize)));
#else
    return Float4{m_depth[pix], m_depth[pix + 1], m_depth[pix + kTileSize], m_depth[pix + kTileSize + 1]};
#endif
  }

  // Writes the depths `z` of a quad's pixels in `live` (bit p for pixel p),
  // from pixel 0's index.
  void store_depths(size_t pix, Float4 z, unsigned live) {
#if defined(__SSE2__)
    if (live == 0xfu) {  // most quads: two pairs
      _mm_storel_pi(reinterpret_cast<__m64*>(m_depth + pix), __m128(z));
      _mm_storeh_pi(reinterpret_cast<__m64*>(m_depth + pix + kTileSize), __m128(z));
      return;
    }
#endif
    for (int p = 0; p < 4; ++p)
      if (live & (1u << p)) m_depth[pix + kPixelOffset[p]] = z[p];
  }

  void raster(const SetupTri& t) {
    const int x0 = std::max(t.minx, m_tx * kTileSize), x1 = std::min(t.maxx, m_tx * kTileSize + kTileSize - 1);
    const int y0 = std::max(t.miny, m_ty * kTileSize), y1 = std::min(t.maxy, m_ty * kTileSize + kTileSize - 1);
    if (x0 > x1 || y0 > y1) return;
    const PreparedPass& pp = m_passes[t.object];
    const Pass& pass = *pp.pass;
    // Early depth test when the shader cannot discard: occluded fragments
    // are never shaded and fetch no texels.
    const bool early_z = !pass.alpha_tested();
    // Without the image, a fragment's colour matters only where its alpha
    // may discard it: other passes record their lines and lookups without
    // fetching, filtering or combining a texel (the same trace, bit for bit).
    const bool shade = m_image || pass.alpha_tested();
    const bool reads_colour = pass.reads_colour(), blended = pass.blended();
    const bool test_depth = pass.depth_func != DepthFunc::always;
    const Float4 colour{pass.colour.x, pass.colour.y, pass.colour.z, pass.colour.w};
    const float ref255 = pass.alpha_ref * 255.0f;
    const bool record = m_settings.record_texture_lines;
    const int qx0 = x0 & ~1, qy0 = y0 & ~1;
#if defined(__SSE2__)
    // Where a triangle's edge values in the tile are 32-bit integers (a
    // small triangle's), four pixels to a register, converted to float by
    // one instruction (the same floats: the same integers, rounded alike).
    const bool narrow = edges_fit_32(t, qx0, qy0, x1 | 1, y1 | 1);
    __m128i offsets[3], bias[3], e32[3];
    if (narrow)
      for (int i = 0; i < 3; ++i) {
        offsets[i] = _mm_setr_epi32(0, int32_t(t.a[i]), int32_t(t.b[i]), int32_t(t.a[i] + t.b[i]));
        bias[i] = _mm_set1_epi32(int32_t(t.bias[i]));
      }
#endif

    // Pixels outside [x0, x1] x [y0, y1] are left out: in x only a row's
    // first quad has any (its left column, when x0 is odd: qx0 < x0) and its
    // last (its right column, when x1 is even: qx_last = x1); in y only the
    // first and last rows.
    const int qx_last = x1 & ~1;
    const unsigned keep_first_x = (x0 & 1) ? ~0x5u : ~0u, keep_last_x = (x1 & 1) ? ~0u : ~0xau;
    for (int qy = qy0; qy <= y1; qy += 2) {
      const int64_t row[3] = {t.b[0] * qy + t.c[0], t.b[1] * qy + t.c[1], t.b[2] * qy + t.c[2]};
      const unsigned keep_y = (qy < y0 ? ~0x3u : ~0u) & (qy + 1 > y1 ? ~0xcu : ~0u);
      // The row's part of the quads' framebuffer lines (line_row()).
      const uint32_t row_line = line_row(qy);
      for (int qx = qx0; qx <= x1; qx += 2) {
        // Edge values at the quad's four pixels: (qx,qy) (qx+1,qy) (qx,qy+1) (qx+1,qy+1).
        int64_t e[3][4];
        unsigned mask;
#if defined(__SSE2__)
        if (narrow) mask = edge_values32(t, qx, row, offsets, bias, e32);
        else
#endif
          mask = edge_values(t, qx, row, e);
        mask &= keep_y & (qx == qx0 ? keep_first_x : ~0u) & (qx == qx_last ? keep_last_x : ~0u);
        if (!mask) continue;
        m_cur.covered += pixels_in(mask);

        // Depth from the plane, evaluated and clamped as llvmpipe does (only
        // covered pixels' are used), and the early depth test, before
        // anything is interpolated: a third of the covered quads of
        // oa:ctf_inyard's frame fail it (performance.md).
        const Float4 z = plane_depth(t, qx, qy, m_fma);

        const uint32_t quad_line = 1u << (row_line + line_column(qx));
        // Pixel p's index in the tile's buffers is quad_pix + kPixelOffset[p]
        // (the quad lies in the tile: tiles start at even coordinates).
        const size_t quad_pix = in_tile(qx, qy);
        unsigned live = mask;
        if (early_z && test_depth) {
          // Every covered pixel reads its depth line (the quad's), and each
          // keeps its own result: the quad's pixels are different pixels.
          m_cur.depth_read_mask |= quad_line;
          live &= depths_passing(pass.depth_func, z, quad_depths(quad_pix));
          if (!live) continue;
        }

        // Barycentrics and interpolated values at all four pixels (helpers
        // included: they provide the derivatives), pixel p in lane p. Each
        // lane does the per-pixel scalar operations in their order (no fused
        // multiply-add: -ffp-contract=off), so every value is that of the
        // pixel-by-pixel code, bit for bit.
        Float4 ef[3];
#if defined(__SSE2__)
        if (narrow)
          for (int i = 0; i < 3; ++i) ef[i] = Float4(_mm_cvtepi32_ps(e32[i]));
        else
#endif
          for (int i = 0; i < 3; ++i) ef[i] = Float4{float(e[i][0]), float(e[i][1]), float(e[i][2]), float(e[i][3])};
        const Float4 b0 = ef[0] * t.inv_area, b1 = ef[1] * t.inv_area, b2 = ef[2] * t.inv_area;
        const Float4 w = 1.0f / (b0 * t.iw[0] + b1 * t.iw[1] + b2 * t.iw[2]);
        const Float4 u = (b0 * t.uw[0] + b1 * t.uw[1] + b2 * t.uw[2]) * w;
        const Float4 v = (b0 * t.vw[0] + b1 * t.vw[1] + b2 * t.vw[2]) * w;
        Float4 lu{}, lv{};
        if (pp.lightmap_coords) {
          lu = (b0 * t.luw[0] + b1 * t.luw[1] + b2 * t.luw[2]) * w;
          lv = (b0 * t.lvw[0] + b1 * t.lvw[1] + b2 * t.lvw[2]) * w;
        }
        if (shade && t.lit != SetupTri::kNoLit) {
          const LitTri& L = m_lit[t.lit];
          const int n = pp.coloured ? kColourVaryings : kLitVaryings;
          for (int k = 0; k < n; ++k) m_lit4[k] = (b0 * L.a[0][k] + b1 * L.a[1][k] + b2 * L.a[2][k]) * w;
        }

        ++m_cur.quads;
        m_cur.shaded += pixels_in(live);

        m_quad_lines.clear();
        detail::QuadLines* lines = record ? &m_quad_lines : nullptr;
        // Each pixel's colour as one vector of its channels (r, g, b, a).
        Float4 c[4];
        if (shade)
          for (int p = 0; p < 4; ++p) c[p] = Float4{255, 255, 255, 255};
        bool first = true;
        const bool deluxe = pass.shading == Shading::deluxe;
        for (size_t li = 0; li < pp.layers.size(); ++li) {
          const PreparedLayer& L = pp.layers[li];
          const Float4 su = L.lightmap_coords ? lu : u;
          const Float4 sv = L.lightmap_coords ? lv : v;
          const Float4 tu = L.transformed ? L.xf.a * su + L.xf.b * sv + L.xf.c : su;
          const Float4 tv = L.transformed ? L.xf.d * su + L.xf.e * sv + L.xf.f : sv;
          if (!shade) {
            // A layer of the last planned one's shape at the same
            // coordinates (a per-pixel lit pass's maps) has its footprint,
            // levels and blocks: only its lines' bases differ.
            const bool again =
                L.texture->shape != 0 && L.texture->shape == m_plan_shape && same_bits(tu, m_plan_u) && same_bits(tv, m_plan_v);
            if (!again) {
              // Its lines depend on the levels alone, not their weights.
              const detail::Footprint f = footprint_of<true>(*L.texture, tu, tv);
              if (f.probes != 1) {
                for (int p = 0; p < 4; ++p)
                  if (live & (1u << p)) detail::sample_lines(*L.texture, tu[p], tv[p], f, lines, m_cur.samples);
                continue;
              }
              detail::plan_quad_lines(*L.texture, tu, tv, f.lambda, m_plan);
              m_plan_shape = L.texture->shape;
              m_plan_u = tu;
              m_plan_v = tv;
            }
            detail::add_quad_lines(*L.texture, m_plan, live, lines, m_cur.samples);
            continue;
          }
          const detail::Footprint f = footprint_of(*L.texture, tu, tv);
          // The live pixels' samples, in pixel order (their lines are recorded so).
          Float4 texel[4];
          if (f.probes == 1) {
            detail::sample_quad(*L.texture, tu, tv, f.lambda, live, lines, m_cur.samples, texel);
          } else {
            for (int p = 0; p < 4; ++p)
              if (live & (1u << p))
                texel[p] = detail::to_float4(detail::sample(*L.texture, tu[p], tv[p], f, lines, m_cur.samples));
          }
          if (L.combine == Combine::fetch && !deluxe) continue;  // sampled (counted), not combined
          // The scalar combine's operations per channel: x * 1 and x / 1
          // are exact, so a lane that a step leaves alone gets the value
          // it had.
          const float k = L.scale / 255.0f;
          const Float4 scale3{L.scale, L.scale, L.scale, 1.0f};
          const Float4 mod_mul{k, k, k, 1.0f}, mod_div{1.0f, 1.0f, 1.0f, 255.0f};
          for (int p = 0; p < 4; ++p) {
            if (!(live & (1u << p))) continue;
            const Float4 s = texel[p];
            if (deluxe) {
              m_texel[p][li] = detail::to_rgba(s);
              continue;
            }
            Float4& o = c[p];
            if (first) {
              // The first layer's texel starts the colour; the pass
              // colour and the vertex colour multiply it (unless it
              // replaces them).
              o = s;
              if (L.scale != 1.0f) o = o * scale3;
              if (!pp.replace) o = o * colour;
              if (pp.coloured) o = o * vertex_colour(p);
            } else if (L.combine == Combine::modulate) {
              // rgb *= s * (scale / 255); a *= s.a / 255
              o = o * (s * mod_mul / mod_div);
            } else {
              // rgb += s * scale; a *= s.a / 255
              const float a = o[3] * (s[3] / 255.0f);
              o = o + s * L.scale;
              o[3] = a;
            }
          }
          first = false;
        }
        if (!shade) {
          // c[p] is not used: the pass's alpha test is `always`.
        } else if (deluxe) {
          for (int p = 0; p < 4; ++p) {
            if (!(live & (1u << p))) continue;
            float lit[kLitVaryings];
            for (int k = 0; k < kLitVaryings; ++k) lit[k] = m_lit4[k][p];
            c[p] = detail::to_float4(shade_deluxe(pp, m_texel[p], lit));
          }
        } else if (first) {  // no layers: the pass colour alone, times any vertex colour
          for (int p = 0; p < 4; ++p) {
            c[p] = c[p] * colour;
            if (pp.coloured) c[p] = c[p] * vertex_colour(p);
          }
        }

        if (!shade) {
          // The trace alone of a pass that cannot discard: every live pixel
          // passed the early depth test (or has none) and is written, what
          // the loop below does pixel by pixel.
          if (pass.depth_write && live) {
            store_depths(quad_pix, z, live);
            m_cur.depth_write_mask |= quad_line;
          }
          m_cur.passed += pixels_in(live);
          if (pass.colour_write && live) {
            if (reads_colour) m_cur.colour_read_mask |= quad_line;
            m_cur.colour_write_mask |= quad_line;
          }
          if (record) m_quad_lines.flush(m_out->lines);
          continue;
        }
        for (int p = 0; p < 4; ++p) {
          if (!(live & (1u << p))) continue;
          if (!alpha_passes(pass.alpha_func, c[p][3], ref255)) continue;  // discard
          const size_t pix = quad_pix + kPixelOffset[p];
          if (!early_z && test_depth) {
            m_cur.depth_read_mask |= quad_line;
            if (!depth_passes(pass.depth_func, z[p], m_depth[pix])) continue;
          }
          if (pass.depth_write) {
            m_depth[pix] = z[p];
            m_cur.depth_write_mask |= quad_line;
          }
          ++m_cur.passed;
          if (!pass.colour_write) continue;  // glColorMask: depth only
          if (reads_colour) m_cur.colour_read_mask |= quad_line;
          m_cur.colour_write_mask |= quad_line;
          if (!m_image) continue;  // the trace alone
          uint8_t* out = m_colour + pix * 4;
          Float4 src = c[p];
          if (blended) {
            // Blending on the unorm frame: the shader's colour is clamped
            // to [0, 1] first (GL 4.5 Section 17.3.6).
            src = clamp4(src, 0.0f, 255.0f);
            const Float4 dst = detail::texel4(out);
            src = src * blend_factor(pass.src, src, dst) + dst * blend_factor(pass.dst, src, dst);
          }
          quantize(src, out);
          m_ids[pix] = t.object;
        }
        if (record) m_quad_lines.flush(m_out->lines);
      }
    }
  }

  // Float to unsigned normalised, per channel: clamp, then round to
  // nearest (the conversion truncates, as uint8_t(c + 0.5f) does).
  static void quantize(Float4 c255, uint8_t* out) {
    const Float4 r = clamp4(c255, 0.0f, 255.0f) + 0.5f;
#if defined(__SSE2__)
    // Truncate to 32 bits, then narrow with saturation: lanes are 0..255,
    // or NaN, which converts to INT_MIN and narrows to 0, as the scalar
    // uint8_t(NaN) gives (the low byte of cvttss2si's INT_MIN).
    const __m128i i = _mm_cvttps_epi32(__m128(r));
    const __m128i b = _mm_packus_epi16(_mm_packs_epi32(i, i), _mm_setzero_si128());
    const int32_t word = _mm_cvtsi128_si32(b);
    std::memcpy(out, &word, 4);
#else
    using Int4 = int32_t __attribute__((vector_size(16)));
    const Byte4 b = __builtin_convertvector(__builtin_convertvector(r, Int4), Byte4);
    std::memcpy(out, &b, 4);
#endif
  }

  // A quad's footprint on a texture from its four pixels' coordinates
  // (pixel 0's right and lower neighbours give the derivatives); with
  // `levels_only`, a level of detail of the same levels (detail::footprint).
  template <bool levels_only = false>
  detail::Footprint footprint_of(const detail::SamplerTexture& tex, Float4 tu, Float4 tv) const {
    const detail::Derivs d{tu[1] - tu[0], tv[1] - tv[0], tu[2] - tu[0], tv[2] - tv[0]};
    return detail::footprint<levels_only>(tex, d, m_settings.max_anisotropy);
  }

  // Pixel p's vertex colour (the first four varyings).
  Float4 vertex_colour(int p) const { return Float4{m_lit4[0][p], m_lit4[1][p], m_lit4[2][p], m_lit4[3][p]}; }

  const std::vector<SetupTri>& m_tris;
  const std::vector<LitTri>& m_lit;
  const std::vector<PreparedPass>& m_passes;
  const PipelineSettings& m_settings;
  static constexpr int kTileShift = __builtin_ctz(unsigned(kTileSize));
  static constexpr int kTilePixels = kTileSize * kTileSize;
  // A quad's pixel p from its pixel 0, in the tile's buffers.
  static constexpr size_t kPixelOffset[4] = {0, 1, kTileSize, kTileSize + 1};
  int m_block_shift_x, m_block_shift_y;
  Frame m_frame;
  bool m_image;  // PipelineSettings::draw_image
  bool m_fma;    // plane_depth by the FMA instruction
  int m_tx = 0, m_ty = 0;
  Output* m_out = nullptr;
  TileWork m_cur;
  bool m_open = false;
  std::vector<uint32_t> m_vids;
  detail::QuadLines m_quad_lines;
  // The trace alone: the last layer's plan of lines, its texture's shape
  // (0: none) and coordinates.
  detail::QuadLinePlan m_plan;
  uint32_t m_plan_shape = 0;
  Float4 m_plan_u{}, m_plan_v{};
  // A per-pixel lit quad's texels, per pixel and layer (shade_deluxe reads
  // one pixel's row); a member so other passes do not initialise it per quad.
  detail::Rgba m_texel[4][kMaxDeluxeLayers];
  // The quad's extra varyings, varying k of pixel p in m_lit4[k][p].
  Float4 m_lit4[kLitVaryings];
  // The tile's pixels, row by row (run()).
  alignas(64) uint8_t m_colour[kTilePixels * 4];
  alignas(64) float m_depth[kTilePixels];
  alignas(64) uint32_t m_ids[kTilePixels];
};

}  // namespace oovr::detail
