// The functional pipeline's geometry stage (renderer.cpp's, included only
// there): each draw's vertices transformed once, projected into each eye,
// clipped against the view volume, snapped and set up as triangles ready to
// rasterise (llvmpipe's draw and setup modules; STYLE.md).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "oovr/core/error.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/sampler.h"
#include "oovr/pipeline/shader_cost.h"

namespace oovr::detail {

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

inline ClipVertex lerp_vertex(const ClipVertex& p, const ClipVertex& q, float t) {
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
inline float plane_distance(int plane, const Vec4& p) {
  switch (plane) {
    case 0: return p.z + p.w;
    case 1: return p.w - p.z;
    case 2: return p.x + p.w;
    case 3: return p.w - p.x;
    case 4: return p.y + p.w;
    default: return p.w - p.y;
  }
}

inline uint32_t outcode(const Vec4& p) {
  uint32_t c = 0;
  for (int i = 0; i < 6; ++i)
    if (plane_distance(i, p) < 0) c |= 1u << i;
  return c;
}

// Whether a draw's pass is multiplied by its mesh's vertex colours (not
// when its first layer replaces the colour, GL_REPLACE).
inline bool uses_vertex_colours(const Scene& scene, const Object& o) {
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

}  // namespace oovr::detail
