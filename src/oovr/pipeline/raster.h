// The functional pipeline's rasteriser (renderer.cpp's, included only
// there): a tile's bin of set-up triangles rasterised in draw order, each
// fragment shaded from its pass's layers, tested, blended and written, and
// the tile's part of the trace recorded (llvmpipe's rast module; STYLE.md).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

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

// Pixels set in a quad's 4-bit mask. A table: without -mpopcnt (oovr is
// built for any x86-64) the builtin is a library call.
inline uint32_t pixels_in(unsigned mask) {
  static constexpr uint8_t kPixels[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
  return kPixels[mask & 15u];
}

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

// A blend factor (0..1) for one channel: s and d are the source and
// destination colours (0..255), k the channel.
inline float blend_factor(BlendFactor f, const detail::Rgba& s, const detail::Rgba& d, int k) {
  const float sc = k == 0 ? s.r : k == 1 ? s.g : k == 2 ? s.b : s.a;
  const float dc = k == 0 ? d.r : k == 1 ? d.g : k == 2 ? d.b : d.a;
  switch (f) {
    case BlendFactor::zero: return 0.0f;
    case BlendFactor::one: return 1.0f;
    case BlendFactor::src_colour: return sc / 255.0f;
    case BlendFactor::one_minus_src_colour: return 1.0f - sc / 255.0f;
    case BlendFactor::src_alpha: return s.a / 255.0f;
    case BlendFactor::one_minus_src_alpha: return 1.0f - s.a / 255.0f;
    case BlendFactor::dst_colour: return dc / 255.0f;
    case BlendFactor::one_minus_dst_colour: return 1.0f - dc / 255.0f;
    case BlendFactor::dst_alpha: return d.a / 255.0f;
    case BlendFactor::one_minus_dst_alpha: return 1.0f - d.a / 255.0f;
  }
  return 0.0f;
}

// Per-tile rasterisation and shading. Writes only the tile's own pixels.
class TileRasterizer {
 public:
  TileRasterizer(const std::vector<SetupTri>& tris, const std::vector<LitTri>& lit, const std::vector<PreparedPass>& passes,
                 const PipelineSettings& settings, int block_w, int block_h, int frame_w, uint8_t* colour, float* depth,
                 uint32_t* ids)
      : m_tris(tris),
        m_lit(lit),
        m_passes(passes),
        m_settings(settings),
        m_block_w(block_w),
        m_block_h(block_h),
        m_frame_w(frame_w),
        m_colour(colour),
        m_depth(depth),
        m_ids(ids) {}

  struct Output {
    std::vector<TileWork> work;
    std::vector<TexLine> lines;
  };

  void run(int tx, int ty, const std::vector<uint32_t>& bin, Output& out) {
    m_tx = tx;
    m_ty = ty;
    m_out = &out;
    m_open = false;
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

 private:
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

  uint32_t line_of_pixel(int x, int y) const {
    const int lx = x - m_tx * kTileSize, ly = y - m_ty * kTileSize;
    return uint32_t((ly / m_block_h) * (kTileSize / m_block_w) + lx / m_block_w);
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
    const bool reads_colour = pass.reads_colour(), blended = pass.blended();
    const bool test_depth = pass.depth_func != DepthFunc::always;
    const float cr = pass.colour.x, cg = pass.colour.y, cb = pass.colour.z, ca = pass.colour.w;
    const float ref255 = pass.alpha_ref * 255.0f;
    const bool record = m_settings.record_texture_lines;
    const int qx0 = x0 & ~1, qy0 = y0 & ~1;

    for (int qy = qy0; qy <= y1; qy += 2) {
      for (int qx = qx0; qx <= x1; qx += 2) {
        // Edge values at the quad's four pixels: (qx,qy) (qx+1,qy) (qx,qy+1) (qx+1,qy+1).
        int64_t e[3][4];
        unsigned mask = 0xf;
        for (int i = 0; i < 3; ++i) {
          const int64_t base = t.a[i] * qx + t.b[i] * qy + t.c[i];
          e[i][0] = base;
          e[i][1] = base + t.a[i];
          e[i][2] = base + t.b[i];
          e[i][3] = base + t.a[i] + t.b[i];
          for (int p = 0; p < 4; ++p)
            if (e[i][p] + t.bias[i] < 0) mask &= ~(1u << p);
        }
        if (qx < x0) mask &= ~0x5u;
        if (qx + 1 > x1) mask &= ~0xau;
        if (qy < y0) mask &= ~0x3u;
        if (qy + 1 > y1) mask &= ~0xcu;
        if (!mask) continue;
        m_cur.covered += pixels_in(mask);

        // Barycentrics and interpolated values at all four pixels (helpers
        // included: they provide the derivatives).
        float z[4], u[4], v[4], lu[4], lv[4], lit[4][kLitVaryings];
        for (int p = 0; p < 4; ++p) {
          const float b0 = float(e[0][p]) * t.inv_area;
          const float b1 = float(e[1][p]) * t.inv_area;
          const float b2 = float(e[2][p]) * t.inv_area;
          // Depth from the plane, evaluated and clamped as llvmpipe does.
          const float zp = std::fma(t.dzdy, float(qy + (p >> 1)), std::fma(t.dzdx, float(qx + (p & 1)), t.z0));
          z[p] = std::max(std::min(zp, 1.0f), 0.0f);
          const float w = 1.0f / (b0 * t.iw[0] + b1 * t.iw[1] + b2 * t.iw[2]);
          u[p] = (b0 * t.uw[0] + b1 * t.uw[1] + b2 * t.uw[2]) * w;
          v[p] = (b0 * t.vw[0] + b1 * t.vw[1] + b2 * t.vw[2]) * w;
          if (pp.lightmap_coords) {
            lu[p] = (b0 * t.luw[0] + b1 * t.luw[1] + b2 * t.luw[2]) * w;
            lv[p] = (b0 * t.lvw[0] + b1 * t.lvw[1] + b2 * t.lvw[2]) * w;
          }
          if (t.lit != SetupTri::kNoLit) {
            const LitTri& L = m_lit[t.lit];
            const int n = pp.coloured ? kColourVaryings : kLitVaryings;
            for (int k = 0; k < n; ++k) lit[p][k] = (b0 * L.a[0][k] + b1 * L.a[1][k] + b2 * L.a[2][k]) * w;
          }
        }

        unsigned live = mask;
        if (early_z && test_depth) {
          for (int p = 0; p < 4; ++p) {
            if (!(live & (1u << p))) continue;
            const int x = qx + (p & 1), y = qy + (p >> 1);
            m_cur.depth_read_mask |= 1u << line_of_pixel(x, y);
            if (!depth_passes(pass.depth_func, z[p], m_depth[size_t(y) * m_frame_w + x])) live &= ~(1u << p);
          }
          if (!live) continue;
        }
        ++m_cur.quads;
        m_cur.shaded += pixels_in(live);

        m_quad_lines.clear();
        detail::QuadLines* lines = record ? &m_quad_lines : nullptr;
        detail::Rgba c[4];
        for (int p = 0; p < 4; ++p) c[p] = {255, 255, 255, 255};
        bool first = true;
        const bool deluxe = pass.shading == Shading::deluxe;
        for (size_t li = 0; li < pp.layers.size(); ++li) {
          const PreparedLayer& L = pp.layers[li];
          const float* su = L.lightmap_coords ? lu : u;
          const float* sv = L.lightmap_coords ? lv : v;
          float tu[4], tv[4];
          for (int p = 0; p < 4; ++p) {
            if (L.transformed) {
              tu[p] = L.xf.a * su[p] + L.xf.b * sv[p] + L.xf.c;
              tv[p] = L.xf.d * su[p] + L.xf.e * sv[p] + L.xf.f;
            } else {
              tu[p] = su[p];
              tv[p] = sv[p];
            }
          }
          const detail::Derivs d{tu[1] - tu[0], tv[1] - tv[0], tu[2] - tu[0], tv[2] - tv[0]};
          const detail::Footprint f = detail::footprint(*L.texture, d, m_settings.max_anisotropy);
          // The live pixels' samples, in pixel order (their lines are recorded so).
          detail::Rgba texel[4];
          if (f.probes == 1) {
            detail::sample_quad(*L.texture, tu, tv, f.lambda, live, lines, m_cur.samples, texel);
          } else {
            for (int p = 0; p < 4; ++p)
              if (live & (1u << p)) texel[p] = detail::sample(*L.texture, tu[p], tv[p], f, lines, m_cur.samples);
          }
          if (L.combine == Combine::fetch && !deluxe) continue;  // sampled (counted), not combined
          for (int p = 0; p < 4; ++p) {
            if (!(live & (1u << p))) continue;
            const detail::Rgba& s = texel[p];
            if (deluxe) {
              m_texel[p][li] = s;
              continue;
            }
            detail::Rgba& o = c[p];
            if (first) {
              // The first layer's texel starts the colour; the pass
              // colour and the vertex colour multiply it (unless it
              // replaces them).
              o = s;
              if (L.scale != 1.0f) {
                o.r *= L.scale;
                o.g *= L.scale;
                o.b *= L.scale;
              }
              if (!pp.replace) {
                o.r *= cr;
                o.g *= cg;
                o.b *= cb;
                o.a *= ca;
              }
              if (pp.coloured) {
                o.r *= lit[p][0];
                o.g *= lit[p][1];
                o.b *= lit[p][2];
                o.a *= lit[p][3];
              }
            } else if (L.combine == Combine::modulate) {
              const float k = L.scale / 255.0f;
              o.r *= s.r * k;
              o.g *= s.g * k;
              o.b *= s.b * k;
              o.a *= s.a / 255.0f;
            } else {
              o.r += s.r * L.scale;
              o.g += s.g * L.scale;
              o.b += s.b * L.scale;
              o.a *= s.a / 255.0f;
            }
          }
          first = false;
        }
        if (deluxe) {
          for (int p = 0; p < 4; ++p)
            if (live & (1u << p)) c[p] = shade_deluxe(pp, m_texel[p], lit[p]);
        } else if (first) {  // no layers: the pass colour alone, times any vertex colour
          for (int p = 0; p < 4; ++p) {
            c[p].r *= cr;
            c[p].g *= cg;
            c[p].b *= cb;
            c[p].a *= ca;
            if (pp.coloured) {
              c[p].r *= lit[p][0];
              c[p].g *= lit[p][1];
              c[p].b *= lit[p][2];
              c[p].a *= lit[p][3];
            }
          }
        }

        for (int p = 0; p < 4; ++p) {
          if (!(live & (1u << p))) continue;
          const int x = qx + (p & 1), y = qy + (p >> 1);
          if (!alpha_passes(pass.alpha_func, c[p].a, ref255)) continue;  // discard
          const size_t pix = size_t(y) * m_frame_w + x;
          const uint32_t line = line_of_pixel(x, y);
          if (!early_z && test_depth) {
            m_cur.depth_read_mask |= 1u << line;
            if (!depth_passes(pass.depth_func, z[p], m_depth[pix])) continue;
          }
          if (pass.depth_write) {
            m_depth[pix] = z[p];
            m_cur.depth_write_mask |= 1u << line;
          }
          uint8_t* out = m_colour + pix * 4;
          detail::Rgba src = c[p];
          if (blended) {
            // Blending on the unorm frame: the shader's colour is clamped
            // to [0, 1] first (GL 4.5 Section 17.3.6).
            src = {std::clamp(src.r, 0.0f, 255.0f), std::clamp(src.g, 0.0f, 255.0f), std::clamp(src.b, 0.0f, 255.0f),
                   std::clamp(src.a, 0.0f, 255.0f)};
            const detail::Rgba dst{float(out[0]), float(out[1]), float(out[2]), float(out[3])};
            detail::Rgba r;
            r.r = src.r * blend_factor(pass.src, src, dst, 0) + dst.r * blend_factor(pass.dst, src, dst, 0);
            r.g = src.g * blend_factor(pass.src, src, dst, 1) + dst.g * blend_factor(pass.dst, src, dst, 1);
            r.b = src.b * blend_factor(pass.src, src, dst, 2) + dst.b * blend_factor(pass.dst, src, dst, 2);
            r.a = src.a * blend_factor(pass.src, src, dst, 3) + dst.a * blend_factor(pass.dst, src, dst, 3);
            src = r;
          }
          ++m_cur.passed;
          if (!pass.colour_write) continue;  // glColorMask: depth only
          if (reads_colour) m_cur.colour_read_mask |= 1u << line;
          out[0] = quantize(src.r);
          out[1] = quantize(src.g);
          out[2] = quantize(src.b);
          out[3] = quantize(src.a);
          m_ids[pix] = t.object;
          m_cur.colour_write_mask |= 1u << line;
        }
        if (record) m_quad_lines.flush(m_out->lines);
      }
    }
  }

  static uint8_t quantize(float c255) {
    // Float to unsigned normalised: clamp, then round to nearest.
    const float c = std::clamp(c255, 0.0f, 255.0f);
    return uint8_t(c + 0.5f);
  }

  const std::vector<SetupTri>& m_tris;
  const std::vector<LitTri>& m_lit;
  const std::vector<PreparedPass>& m_passes;
  const PipelineSettings& m_settings;
  int m_block_w, m_block_h, m_frame_w;
  uint8_t* m_colour;
  float* m_depth;
  uint32_t* m_ids;
  int m_tx = 0, m_ty = 0;
  Output* m_out = nullptr;
  TileWork m_cur;
  bool m_open = false;
  std::vector<uint32_t> m_vids;
  detail::QuadLines m_quad_lines;
  // A per-pixel lit quad's texels, per pixel and layer (shade_deluxe reads
  // one pixel's row); a member so other passes do not initialise it per quad.
  detail::Rgba m_texel[4][kMaxDeluxeLayers];
};

}  // namespace oovr::detail
