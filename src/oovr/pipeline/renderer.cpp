// The functional stereo pipeline. Structure follows llvmpipe's split
// (STYLE.md): triangle setup and binning into 16x16 tiles, then
// rasterisation of each tile's bin in draw order, tiles in parallel. Each tile
// owns its framebuffer pixels and its part of the trace, so the result is the
// same for any number of threads.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>

#include "oovr/core/error.h"
#include "oovr/core/parallel.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/sampler.h"
#include "oovr/pipeline/shader_cost.h"

namespace oovr {

namespace {

constexpr int kSubpixelBits = 8;  // llvmpipe's FIXED_ORDER: 1/256 pixel
constexpr float kSubpixelScale = float(1 << kSubpixelBits);

// A draw's extra varyings: per-pixel lighting's (Shading::deluxe) tangent
// frame S, T, N and the tangent-space direction to the eye, as DarkPlaces'
// vertex shader hands them to its fragment shader; or a vertex colour's
// RGBA (0..1), OpenGL's primary colour, in the first four.
constexpr int kLitVaryings = 12;
constexpr int kColourVaryings = 4;

struct ClipVertex {
  Vec4 pos;
  float u, v, lu, lv;
  bool generated;           // made by the clipper (its window position is computed without FMA)
  float lit[kLitVaryings];  // only for per-pixel lit passes
};

// A lit triangle's varyings divided by w at each vertex (perspective-correct
// interpolation, as SetupTri's uw, vw).
struct LitTri {
  float a[3][kLitVaryings];
};

// A triangle after clipping, projection and snapping, ready to rasterise.
// Edge i runs from vertex i+1 to vertex i+2; E_i(px, py) = a*px + b*py + c at
// the centre of pixel (px, py), positive inside (counter-clockwise winding).
struct SetupTri {
  uint32_t object;
  uint32_t eye;
  int32_t minx, maxx, miny, maxy;  // covered pixels lie in this box (inclusive)
  int64_t a[3], b[3], c[3];
  int64_t bias[3];  // 0 on fill-rule edges (pixels on them are inside), -1 otherwise
  float inv_area;
  // Depth plane z(px, py) = fma(dzdy, py, fma(dzdx, px, z0)) at pixel centres.
  float dzdx, dzdy, z0;
  float iw[3], uw[3], vw[3], luw[3], lvw[3];
  uint32_t vid[3];        // mesh vertices of the source triangle
  uint32_t lit = kNoLit;  // index of its LitTri, for per-pixel lit passes
  static constexpr uint32_t kNoLit = ~0u;
};

ClipVertex lerp_vertex(const ClipVertex& p, const ClipVertex& q, float t) {
  ClipVertex r;
  r.pos = {p.pos.x + (q.pos.x - p.pos.x) * t, p.pos.y + (q.pos.y - p.pos.y) * t, p.pos.z + (q.pos.z - p.pos.z) * t,
           p.pos.w + (q.pos.w - p.pos.w) * t};
  r.u = p.u + (q.u - p.u) * t;
  r.v = p.v + (q.v - p.v) * t;
  r.lu = p.lu + (q.lu - p.lu) * t;
  r.lv = p.lv + (q.lv - p.lv) * t;
  for (int k = 0; k < kLitVaryings; ++k) r.lit[k] = p.lit[k] + (q.lit[k] - p.lit[k]) * t;
  r.generated = true;
  return r;
}

// Plane distances (inside >= 0) of the view volume: near, far, left, right,
// bottom, top. Triangles are clipped against all six, as OpenGL specifies
// and as llvmpipe does whenever a depth buffer is bound; pixels outside the
// eye's viewport are also scissored.
float plane_distance(int plane, const Vec4& p) {
  switch (plane) {
    case 0: return p.z + p.w;
    case 1: return p.w - p.z;
    case 2: return p.x + p.w;
    case 3: return p.w - p.x;
    case 4: return p.y + p.w;
    default: return p.w - p.y;
  }
}

uint32_t outcode(const Vec4& p) {
  uint32_t c = 0;
  for (int i = 0; i < 6; ++i)
    if (plane_distance(i, p) < 0) c |= 1u << i;
  return c;
}

// Whether a draw's pass is multiplied by its mesh's vertex colours (not
// when its first layer replaces the colour, GL_REPLACE).
bool uses_vertex_colours(const Scene& scene, const Object& o) {
  const Pass& pass = scene.pass_of(o);
  return !scene.meshes[size_t(o.mesh)].colours.empty() && pass.shading == Shading::layers &&
         !(!pass.layers.empty() && pass.layers.front().combine == Combine::replace);
}

class GeometryStage {
 public:
  GeometryStage(const Scene& scene, const std::vector<Object>& draws, const StereoView& view)
      : m_scene(scene), m_draws(draws), m_view(view) {}

  // Transforms object o once (SMP: world-space positions shared by both
  // eyes), projects into each eye and appends set-up triangles.
  void run(uint32_t o, std::vector<SetupTri>& out, std::vector<LitTri>& lit_out, ObjectWork& work) {
    const Object& obj = m_draws[o];
    const Mesh& mesh = m_scene.meshes[size_t(obj.mesh)];
    const Material& mat = m_scene.materials[size_t(obj.material)];
    const Pass& pass = m_scene.pass_of(obj);
    const bool lit = pass.shading == Shading::deluxe;
    const bool coloured = uses_vertex_colours(m_scene, obj);
    m_lit_out = lit || coloured ? &lit_out : nullptr;
    m_obj = &obj;
    m_pass = &pass;
    work.vertices = uint32_t(mesh.vertices.size());
    work.triangles = uint32_t(mesh.triangle_count());
    work.vertex_bytes = mesh.vertex_bytes();
    work.index_bytes = mesh.indices.size() * sizeof(uint32_t);
    // World positions (shared by both eyes) only for world draws: a captured
    // draw is transformed per eye by one composed matrix below.
    if (obj.view == DrawView::world) {
      m_world.resize(mesh.vertices.size());
      for (size_t i = 0; i < mesh.vertices.size(); ++i)
        m_world[i] = transform_point3(obj.world_from_object, mesh.vertices[i].position);
    }
    if (lit) {
      m_frames.resize(mesh.vertices.size());
      for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        const TangentFrame& f = mesh.frames[i];
        m_frames[i] = {transform_direction(obj.world_from_object, f.s), transform_direction(obj.world_from_object, f.t),
                       transform_direction(obj.world_from_object, f.n)};
      }
    }
    for (int e = 0; e < m_view.eyes; ++e) {
      m_clip.resize(mesh.vertices.size());
      m_codes.resize(mesh.vertices.size());
      if (obj.view == DrawView::world) {
        const Mat4& clip_from_world = m_view.clip_from_world[e];
        for (size_t i = 0; i < mesh.vertices.size(); ++i) m_clip[i] = transform_point(clip_from_world, m_world[i]);
      } else {
        // A captured draw: its own projection, re-projected from this eye's
        // offset from the head (3-D), or alike in both eyes (2-D). One
        // composed matrix, as OpenGL's fixed-function vertex stage uses.
        Mat4 clip_from_object = obj.clip_from_eye * obj.world_from_object;
        if (obj.view == DrawView::captured && m_view.eye_offset_m[e] != 0.0f)
          clip_from_object =
              obj.clip_from_eye * (translate({-m_view.eye_offset_m[e] / m_scene.metres_per_unit, 0, 0}) * obj.world_from_object);
        for (size_t i = 0; i < mesh.vertices.size(); ++i)
          m_clip[i] = transform_point(clip_from_object, mesh.vertices[i].position);
      }
      for (size_t i = 0; i < mesh.vertices.size(); ++i) m_codes[i] = outcode(m_clip[i]);
      for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
        const uint32_t c0 = m_codes[i0], c1 = m_codes[i1], c2 = m_codes[i2];
        if (c0 & c1 & c2) {  // wholly outside one plane of the view volume
          ++work.culled[e];
          continue;
        }
        const uint32_t vid[3] = {i0, i1, i2};
        ClipVertex v[3];
        for (int k = 0; k < 3; ++k) {
          const Vertex& src = mesh.vertices[vid[k]];
          v[k] = {m_clip[vid[k]], src.uv.x, src.uv.y, src.lm_uv.x, src.lm_uv.y, false, {}};
          if (lit) {
            // DarkPlaces' vertex shader: the frame, and the eye's direction
            // taken into it (EyeVector), per vertex.
            const TangentFrame& f = m_frames[vid[k]];
            const Vec3 eye = m_view.eye_position[e] - m_world[vid[k]];
            const float vals[kLitVaryings] = {f.s.x, f.s.y, f.s.z, f.t.x,         f.t.y,         f.t.z,
                                              f.n.x, f.n.y, f.n.z, dot(eye, f.s), dot(eye, f.t), dot(eye, f.n)};
            std::copy(vals, vals + kLitVaryings, v[k].lit);
          } else if (coloured) {
            const uint32_t c = mesh.colours[vid[k]];
            for (int ch = 0; ch < kColourVaryings; ++ch) v[k].lit[ch] = float((c >> (8 * ch)) & 255u) / 255.0f;
          }
        }
        const uint32_t clip_planes = c0 | c1 | c2;
        if (!clip_planes) {
          if (!setup(o, e, mat, v[0], v[1], v[2], vid, out)) ++work.culled[e];
          else ++work.setup[e];
          continue;
        }
        ++work.clipped[e];
        const int produced = clip_and_setup(o, e, mat, v, vid, clip_planes, out);
        work.setup[e] += uint32_t(produced);
        if (produced == 0) ++work.culled[e];
      }
    }
  }

 private:
  int clip_and_setup(uint32_t o, int e, const Material& mat, const ClipVertex (&tri)[3], const uint32_t (&vid)[3],
                     uint32_t planes, std::vector<SetupTri>& out) {
    // Sutherland-Hodgman in homogeneous clip space; attributes are linear
    // there, so plain interpolation is exact.
    std::array<ClipVertex, 12> a, b;
    int n = 3;
    std::copy(tri, tri + 3, a.begin());
    for (int p = 0; p < 6 && n >= 3; ++p) {
      if (!(planes & (1u << p))) continue;
      int m = 0;
      for (int i = 0; i < n; ++i) {
        const ClipVertex& cur = a[size_t(i)];
        const ClipVertex& nxt = a[size_t((i + 1) % n)];
        const float dc = plane_distance(p, cur.pos);
        const float dn = plane_distance(p, nxt.pos);
        if (dc >= 0) b[size_t(m++)] = cur;
        if ((dc >= 0) != (dn >= 0)) {
          // As llvmpipe's clipper: from the outside vertex towards the
          // inside one, t = d_out / (d_out - d_in).
          const bool cur_out = dc < 0;
          const ClipVertex& out_v = cur_out ? cur : nxt;
          const ClipVertex& in_v = cur_out ? nxt : cur;
          const float d_out = cur_out ? dc : dn, d_in = cur_out ? dn : dc;
          b[size_t(m++)] = lerp_vertex(out_v, in_v, d_out / (d_out - d_in));
        }
      }
      n = m;
      std::swap(a, b);
    }
    int produced = 0;
    for (int i = 1; i + 1 < n; ++i) produced += setup(o, e, mat, a[0], a[size_t(i)], a[size_t(i + 1)], vid, out) ? 1 : 0;
    return produced;
  }

  // Projects, snaps and sets up one triangle; false when it is culled
  // (back-facing, empty, or outside the eye's viewport).
  bool setup(uint32_t o, int e, const Material& mat, ClipVertex v0, ClipVertex v1, ClipVertex v2, const uint32_t (&vid_in)[3],
             std::vector<SetupTri>& out) {
    const Viewport& vp = m_view.viewport[e];
    // Viewport transform as OpenGL specifies it (GL 4.5 Section 13.6.1):
    // x_w = x_d * (w / 2) + (x + w / 2), z_w = z_d / 2 + 1 / 2.
    const float sx = float(vp.width) * 0.5f, tx = float(vp.x) + float(vp.width) * 0.5f;
    const float sy = float(vp.height) * 0.5f, ty = float(vp.y) + float(vp.height) * 0.5f;
    ClipVertex* v[3] = {&v0, &v1, &v2};
    uint32_t vid[3] = {vid_in[0], vid_in[1], vid_in[2]};
    int64_t X[3], Y[3];
    float xw[3], yw[3], zw[3], iw[3];
    for (int k = 0; k < 3; ++k) {
      // Clipping leaves w >= 0; w == 0 (a point at the eye) or a non-finite
      // position cannot be projected, and would overflow the fixed-point
      // edge arithmetic below.
      if (!(v[k]->pos.w > 0.0f)) return false;
      iw[k] = 1.0f / v[k]->pos.w;
      if (v[k]->generated) {
        // Clipper-made vertices: plain multiply-add, as llvmpipe's clipper.
        xw[k] = v[k]->pos.x * iw[k] * sx + tx;
        yw[k] = v[k]->pos.y * iw[k] * sy + ty;
        zw[k] = v[k]->pos.z * iw[k] * 0.5f + 0.5f;
      } else {
        // Vertex-stage positions: llvmpipe's draw module fuses the viewport
        // scale and translation (llvm.fmuladd, an FMA on x86-64 with FMA).
        xw[k] = std::fma(v[k]->pos.x * iw[k], sx, tx);
        yw[k] = std::fma(v[k]->pos.y * iw[k], sy, ty);
        zw[k] = std::fma(v[k]->pos.z * iw[k], 0.5f, 0.5f);
      }
      if (!(std::abs(xw[k]) < 1e6f && std::abs(yw[k]) < 1e6f)) return false;
      // Snap to 1/256 pixel, with pixel centres at integer positions.
      X[k] = std::lrint((xw[k] - 0.5f) * kSubpixelScale);
      Y[k] = std::lrint((yw[k] - 0.5f) * kSubpixelScale);
    }
    // llvmpipe orders the vertices by the sign of this area before computing
    // interpolation planes relative to the first one; doing the same makes
    // depth values bit-identical, so depth-test ties resolve the same way.
    const int64_t lp_area = (X[0] - X[1]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[0] - Y[1]);
    if (lp_area == 0) return false;
    const int r0 = lp_area < 0 ? 1 : 0, r1 = lp_area < 0 ? 0 : 1;
    const float dx01 = xw[r0] - xw[r1], dy01 = yw[r0] - yw[r1];
    const float dx20 = xw[2] - xw[r0], dy20 = yw[2] - yw[r0];
    const float ooa = 1.0f / (dx01 * dy20 - dy01 * dx20);
    const float dz01 = zw[r0] - zw[r1], dz20 = zw[2] - zw[r0];
    const float dzdx = dz01 * (dy20 * ooa) - dz20 * (dy01 * ooa);
    const float dzdy = dz20 * (dx01 * ooa) - dz01 * (dx20 * ooa);
    const float z0 = zw[r0] - (dzdx * (xw[r0] - 0.5f) + dzdy * (yw[r0] - 0.5f));

    int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    // Front faces wind counter-clockwise; a material culls back faces, or
    // front faces (glCullFace(GL_FRONT)), or none.
    if (!mat.two_sided && (area < 0) != mat.cull_front) return false;
    if (area < 0) {
      std::swap(X[1], X[2]);
      std::swap(Y[1], Y[2]);
      std::swap(iw[1], iw[2]);
      std::swap(v[1], v[2]);
      std::swap(vid[1], vid[2]);
      area = -area;
    }
    const int64_t minX = std::min({X[0], X[1], X[2]}), maxX = std::max({X[0], X[1], X[2]});
    const int64_t minY = std::min({Y[0], Y[1], Y[2]}), maxY = std::max({Y[0], Y[1], Y[2]});
    auto ceil_div = [](int64_t a, int64_t b) { return a >= 0 ? (a + b - 1) / b : -((-a) / b); };
    auto floor_div = [](int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
    SetupTri t;
    t.minx = int32_t(std::max<int64_t>(ceil_div(minX, 1 << kSubpixelBits), vp.x));
    t.maxx = int32_t(std::min<int64_t>(floor_div(maxX, 1 << kSubpixelBits), vp.x + vp.width - 1));
    t.miny = int32_t(std::max<int64_t>(ceil_div(minY, 1 << kSubpixelBits), vp.y));
    t.maxy = int32_t(std::min<int64_t>(floor_div(maxY, 1 << kSubpixelBits), vp.y + vp.height - 1));
    const ViewRect& r = m_obj->scissor;
    if (!r.whole()) {
      // glScissor and a sub-window glViewport, in this eye's viewport.
      const auto px = [](float f, int size) { return int(std::floor(f * float(size) + 0.5f)); };
      t.minx = std::max(t.minx, vp.x + px(r.x0, vp.width));
      t.maxx = std::min(t.maxx, vp.x + px(r.x1, vp.width) - 1);
      t.miny = std::max(t.miny, vp.y + px(r.y0, vp.height));
      t.maxy = std::min(t.maxy, vp.y + px(r.y1, vp.height) - 1);
    }
    if (t.minx > t.maxx || t.miny > t.maxy) return false;
    t.object = o;
    t.eye = uint32_t(e);
    t.dzdx = dzdx;
    t.dzdy = dzdy;
    t.z0 = z0;
    if (m_pass->offset_factor != 0 || m_pass->offset_units != 0) {
      // glPolygonOffset (GL 4.5 Section 14.6.5): factor x the largest depth
      // slope + units x the smallest resolvable difference of a 24-bit
      // depth buffer.
      t.z0 += m_pass->offset_factor * std::max(std::abs(dzdx), std::abs(dzdy)) + m_pass->offset_units * (1.0f / 16777216.0f);
    }
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      const int64_t dx = X[k] - X[j], dy = Y[k] - Y[j];
      // E(P) = dx * (Py - Yj) - dy * (Px - Xj), with P = 256 * pixel index.
      t.a[i] = -dy * (1 << kSubpixelBits);
      t.b[i] = dx * (1 << kSubpixelBits);
      t.c[i] = dy * X[j] - dx * Y[j];
      // Fill rule for pixel centres exactly on an edge. llvmpipe applies the
      // top-left rule in its own y-down view of memory, where row 0 is
      // OpenGL's bottom row; in OpenGL window coordinates (y up) that is a
      // bottom-left rule. With counter-clockwise winding the interior lies
      // left of each edge: a left edge runs downwards (dy < 0), a bottom edge
      // runs rightwards (dy == 0, dx > 0). Pixels on those edges are inside.
      const bool top_left = dy < 0 || (dy == 0 && dx > 0);
      t.bias[i] = top_left ? 0 : -1;
      t.iw[i] = iw[i];
      t.uw[i] = v[i]->u * iw[i];
      t.vw[i] = v[i]->v * iw[i];
      t.luw[i] = v[i]->lu * iw[i];
      t.lvw[i] = v[i]->lv * iw[i];
      t.vid[i] = vid[i];
    }
    if (m_lit_out) {
      LitTri l;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < kLitVaryings; ++k) l.a[i][k] = v[i]->lit[k] * iw[i];
      t.lit = uint32_t(m_lit_out->size());
      m_lit_out->push_back(l);
    }
    t.inv_area = float(1.0 / double(area));
    out.push_back(t);
    return true;
  }

  const Scene& m_scene;
  const std::vector<Object>& m_draws;
  const StereoView& m_view;
  const Object* m_obj = nullptr;
  const Pass* m_pass = nullptr;
  std::vector<Vec3> m_world;
  std::vector<TangentFrame> m_frames;
  std::vector<LitTri>* m_lit_out = nullptr;
  std::vector<Vec4> m_clip;
  std::vector<uint32_t> m_codes;
};

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
detail::Rgba shade_deluxe(const PreparedPass& pp, const detail::Rgba* texel, const float* lit) {
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

bool depth_passes(DepthFunc f, float z, float stored) {
  switch (f) {
    case DepthFunc::less: return z < stored;
    case DepthFunc::lequal: return z <= stored;
    case DepthFunc::equal: return z == stored;
    case DepthFunc::always: return true;
  }
  return false;
}

bool alpha_passes(AlphaFunc f, float a, float ref255) {
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
float blend_factor(BlendFactor f, const detail::Rgba& s, const detail::Rgba& d, int k) {
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

}  // namespace

FrameOutput render_frame(const Scene& scene, const StereoView& view, const PipelineSettings& settings, int frame) {
  settings.validate();
  FrameOutput result;
  FrameTrace& trace = result.trace;
  trace.frame = frame;
  trace.frame_width = view.frame_width;
  trace.frame_height = view.frame_height;
  trace.tile_size = kTileSize;
  trace.tiles_x = (view.frame_width + kTileSize - 1) / kTileSize;
  trace.tiles_y = (view.frame_height + kTileSize - 1) / kTileSize;
  trace.line_bytes = settings.line_bytes;
  trace.texture_format = settings.texture_format;
  line_block_shape(settings.line_bytes, trace.block_w, trace.block_h);
  const std::vector<Object>& draws = scene.draws(frame);
  trace.objects.resize(draws.size());

  // Geometry: objects in parallel, each into its own list, then concatenated
  // in draw order so that bins keep draw order.
  std::vector<std::vector<SetupTri>> per_object(draws.size());
  std::vector<std::vector<LitTri>> per_object_lit(draws.size());
  const unsigned threads = settings.threads ? settings.threads : default_thread_count();
  {
    const size_t chunks = std::min<size_t>(draws.size(), size_t(threads) * 8);
    parallel_for(chunks, threads, [&](size_t c) {
      GeometryStage stage(scene, draws, view);
      const size_t begin = draws.size() * c / chunks, end = draws.size() * (c + 1) / chunks;
      for (size_t o = begin; o < end; ++o) stage.run(uint32_t(o), per_object[o], per_object_lit[o], trace.objects[o]);
    });
  }
  std::vector<SetupTri> tris;
  std::vector<LitTri> lit;
  {
    size_t n = 0;
    for (const auto& v : per_object) n += v.size();
    tris.reserve(n);
    for (size_t o = 0; o < per_object.size(); ++o) {
      const uint32_t base = uint32_t(lit.size());
      for (SetupTri& t : per_object[o])
        if (t.lit != SetupTri::kNoLit) t.lit += base;
      tris.insert(tris.end(), per_object[o].begin(), per_object[o].end());
      lit.insert(lit.end(), per_object_lit[o].begin(), per_object_lit[o].end());
      std::vector<SetupTri>().swap(per_object[o]);
      std::vector<LitTri>().swap(per_object_lit[o]);
    }
  }

  // Binning: a triangle goes to every tile its box overlaps unless one of its
  // edges has the whole tile outside.
  const int tiles_x = trace.tiles_x, tiles_y = trace.tiles_y;
  std::vector<std::vector<uint32_t>> bins(size_t(tiles_x) * tiles_y);
  for (uint32_t id = 0; id < tris.size(); ++id) {
    const SetupTri& t = tris[id];
    for (int ty = t.miny / kTileSize; ty <= t.maxy / kTileSize; ++ty)
      for (int tx = t.minx / kTileSize; tx <= t.maxx / kTileSize; ++tx) {
        const int px0 = std::max(t.minx, tx * kTileSize), px1 = std::min(t.maxx, tx * kTileSize + kTileSize - 1);
        const int py0 = std::max(t.miny, ty * kTileSize), py1 = std::min(t.maxy, ty * kTileSize + kTileSize - 1);
        bool outside = false;
        for (int i = 0; i < 3 && !outside; ++i) {
          const int64_t ex = t.a[i] > 0 ? px1 : px0, ey = t.b[i] > 0 ? py1 : py0;
          outside = t.a[i] * ex + t.b[i] * ey + t.c[i] + t.bias[i] < 0;
        }
        if (!outside) bins[size_t(ty) * tiles_x + tx].push_back(id);
      }
  }

  // Rasterisation: tiles in parallel.
  result.colour = Image(view.frame_width, view.frame_height);
  for (size_t i = 3; i < result.colour.rgba.size(); i += 4) result.colour.rgba[i] = 255;  // clear to opaque black
  std::vector<float> depth(size_t(view.frame_width) * view.frame_height, 1.0f);
  result.object_id.assign(depth.size(), kNoObject);
  std::vector<detail::SamplerTexture> textures;
  textures.reserve(scene.textures.size());
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    int bw = 0, bh = 0;
    texture_line_shape(scene.textures[i], settings.texture_format, settings.line_bytes, bw, bh);
    textures.emplace_back(uint32_t(i), scene.textures[i], bw, bh);
  }
  // Each draw's pass, its layers' coordinate transforms at this frame's time.
  const double seconds = scene.camera.seconds(frame);
  std::vector<PreparedPass> passes(draws.size());
  for (size_t o = 0; o < draws.size(); ++o) {
    const Pass& pass = scene.pass_of(draws[o]);
    PreparedPass& pp = passes[o];
    pp.pass = &pass;
    pp.coloured = uses_vertex_colours(scene, draws[o]);
    pp.replace = !pass.layers.empty() && pass.layers.front().combine == Combine::replace;
    for (const TextureLayer& l : pass.layers) {
      const UvTransform xf = l.transform(seconds);
      const bool lm = l.coords == TexCoords::lightmap;
      pp.layers.push_back({&textures[size_t(l.texture)], lm, !xf.identity(), xf, l.combine, l.scale});
      pp.lightmap_coords = pp.lightmap_coords || lm;
    }
    if (pass.shading == Shading::deluxe) {
      if (pass.layers.size() > kMaxDeluxeLayers)
        throw Error("a per-pixel lit pass samples " + std::to_string(pass.layers.size()) + " layers; at most " +
                    std::to_string(kMaxDeluxeLayers) + " are supported");
      pp.diffuse = pass.layer(LayerKind::diffuse);
      pp.normal = pass.layer(LayerKind::normal);
      pp.gloss = pass.layer(LayerKind::gloss);
      pp.glow = pass.layer(LayerKind::glow);
      pp.lightmap = pass.layer(LayerKind::lightmap);
      pp.deluxe = pass.layer(LayerKind::deluxe);
      if (pp.diffuse < 0 || pp.lightmap < 0 || pp.deluxe < 0)
        throw Error("a per-pixel lit pass needs diffuse, lightmap and deluxe layers");
    }
    trace.objects[o].fragment_instructions = fragment_instructions(pass);
    trace.objects[o].texture_layers = uint32_t(pass.layers.size());
  }
  std::vector<TileRasterizer::Output> outputs(bins.size());
  parallel_for(bins.size(), threads, [&](size_t i) {
    if (bins[i].empty()) return;
    TileRasterizer r(tris, lit, passes, settings, trace.block_w, trace.block_h, view.frame_width, result.colour.rgba.data(),
                     depth.data(), result.object_id.data());
    r.run(int(i % size_t(tiles_x)), int(i / size_t(tiles_x)), bins[i], outputs[i]);
  });

  // Merge the tiles' records into (object, eye, tile) order.
  struct Ref {
    uint32_t tile;
    uint32_t index;
  };
  std::vector<Ref> refs;
  for (uint32_t i = 0; i < outputs.size(); ++i)
    for (uint32_t k = 0; k < outputs[i].work.size(); ++k) refs.push_back({i, k});
  auto key = [&](const Ref& r) {
    const TileWork& w = outputs[r.tile].work[r.index];
    return std::make_tuple(w.object, w.eye, r.tile);
  };
  std::sort(refs.begin(), refs.end(), [&](const Ref& a, const Ref& b) { return key(a) < key(b); });
  trace.tiles.reserve(refs.size());
  size_t total_lines = 0;
  for (const auto& o : outputs) total_lines += o.lines.size();
  trace.tex_lines.reserve(total_lines);
  for (const Ref& r : refs) {
    TileWork w = outputs[r.tile].work[r.index];
    const auto& src = outputs[r.tile].lines;
    const uint64_t begin = trace.tex_lines.size();
    trace.tex_lines.insert(trace.tex_lines.end(), src.begin() + long(w.tex_begin), src.begin() + long(w.tex_begin + w.tex_count));
    w.tex_begin = begin;
    trace.tiles.push_back(w);
  }
  return result;
}

}  // namespace oovr
