#include "oovr/scene/builtin/procedural.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "oovr/core/parallel.h"
#include "oovr/core/rng.h"

namespace oovr::procedural {

// ---------------------------------------------------------------- meshes

static void quad_indices(Mesh& m, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  // a b c d counter-clockwise
  m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
}

// A parametric patch of nx x ny cells: position(fu, fv) places the vertex at
// parameters fu, fv in [0, 1]; uv repeats rx x ry times; the lightmap
// coordinates span the patch once. Faces are counter-clockwise when +fu runs
// right and +fv up as seen from the front; `inward` flips them.
template <class Position>
static Mesh patch(const char* name, int nx, int ny, float rx, float ry, Position position, bool inward = false) {
  Mesh m;
  m.name = name;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const float fu = float(i) / float(nx), fv = float(j) / float(ny);
      Vertex v;
      v.position = position(fu, fv);
      v.uv = {fu * rx, fv * ry};
      v.lm_uv = {fu, fv};
      m.vertices.push_back(v);
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = uint32_t(j * (nx + 1) + i), b = a + 1, c = b + uint32_t(nx + 1), d = a + uint32_t(nx + 1);
      if (inward) quad_indices(m, a, d, c, b);
      else quad_indices(m, a, b, c, d);
    }
  return m;
}

Mesh grid(float sx, float sz, int nx, int nz, float rx, float rz) {
  return patch("grid", nx, nz, rx, rz, [=](float fu, float fv) { return Vec3{(fu - 0.5f) * sx, 0, (0.5f - fv) * sz}; });
}

Mesh wall(float w, float h, int nx, int ny, float rx, float ry) {
  return patch("wall", nx, ny, rx, ry, [=](float fu, float fv) { return Vec3{(fu - 0.5f) * w, fv * h, 0}; });
}

Mesh box(Vec3 h, float k) {
  Mesh m;
  m.name = "box";
  // Each face: origin corner, two edge vectors (counter-clockwise seen from outside).
  const struct {
    Vec3 o, e1, e2;
  } faces[6] = {
      {{-h.x, -h.y, h.z}, {2 * h.x, 0, 0}, {0, 2 * h.y, 0}},   // +Z
      {{h.x, -h.y, -h.z}, {-2 * h.x, 0, 0}, {0, 2 * h.y, 0}},  // -Z
      {{h.x, -h.y, h.z}, {0, 0, -2 * h.z}, {0, 2 * h.y, 0}},   // +X
      {{-h.x, -h.y, -h.z}, {0, 0, 2 * h.z}, {0, 2 * h.y, 0}},  // -X
      {{-h.x, h.y, h.z}, {2 * h.x, 0, 0}, {0, 0, -2 * h.z}},   // +Y
      {{-h.x, -h.y, -h.z}, {2 * h.x, 0, 0}, {0, 0, 2 * h.z}},  // -Y
  };
  for (const auto& f : faces) {
    const uint32_t base = uint32_t(m.vertices.size());
    const float lu = length(f.e1) * k, lv = length(f.e2) * k;
    const Vec3 p[4] = {f.o, f.o + f.e1, f.o + f.e1 + f.e2, f.o + f.e2};
    const Vec2 uv[4] = {{0, 0}, {lu, 0}, {lu, lv}, {0, lv}};
    for (int i = 0; i < 4; ++i) {
      Vertex v;
      v.position = p[i];
      v.uv = uv[i];
      v.lm_uv = {uv[i].x / std::max(lu, 1e-6f), uv[i].y / std::max(lv, 1e-6f)};
      m.vertices.push_back(v);
    }
    quad_indices(m, base, base + 1, base + 2, base + 3);
  }
  return m;
}

Mesh cylinder(float r, float height, int seg, int rings, float ru, float rv, bool caps) {
  Mesh m = patch("cylinder", seg, rings, ru, rv, [=](float fu, float fv) {
    const float a = 2 * kPi * fu;
    return Vec3{r * std::sin(a), height * fv, r * std::cos(a)};
  });
  if (caps) {
    for (int top = 0; top < 2; ++top) {
      const float y = top ? height : 0;
      const uint32_t centre = uint32_t(m.vertices.size());
      Vertex c;
      c.position = {0, y, 0};
      c.uv = {0.5f, 0.5f};
      m.vertices.push_back(c);
      for (int i = 0; i <= seg; ++i) {
        const float a = 2 * kPi * float(i) / float(seg);
        Vertex v;
        v.position = {r * std::sin(a), y, r * std::cos(a)};
        v.uv = {0.5f + 0.5f * std::sin(a), 0.5f + 0.5f * std::cos(a)};
        m.vertices.push_back(v);
      }
      for (int i = 0; i < seg; ++i) {
        const uint32_t a = centre + 1 + uint32_t(i), b = a + 1;
        if (top) m.indices.insert(m.indices.end(), {centre, a, b});
        else m.indices.insert(m.indices.end(), {centre, b, a});
      }
    }
  }
  return m;
}

Mesh sphere(float r, int seg, int rings, float ru, float rv) {
  Mesh m;
  m.name = "sphere";
  for (int j = 0; j <= rings; ++j) {
    const float phi = kPi * float(j) / float(rings);  // 0 at the bottom pole
    for (int i = 0; i <= seg; ++i) {
      const float a = 2 * kPi * float(i) / float(seg);
      Vertex v;
      v.position = {r * std::sin(phi) * std::sin(a), -r * std::cos(phi), r * std::sin(phi) * std::cos(a)};
      v.uv = {ru * float(i) / float(seg), rv * float(j) / float(rings)};
      v.lm_uv = {float(i) / float(seg), float(j) / float(rings)};
      m.vertices.push_back(v);
    }
  }
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < seg; ++i) {
      const uint32_t a = uint32_t(j * (seg + 1) + i);
      const uint32_t b = a + 1, c = a + 1 + uint32_t(seg + 1), d = a + uint32_t(seg + 1);
      if (j > 0) m.indices.insert(m.indices.end(), {a, b, c});
      if (j < rings - 1) m.indices.insert(m.indices.end(), {a, c, d});
    }
  return m;
}

Mesh torus(float R, float r, int seg, int sides, float ru, float rv) {
  return patch("torus", seg, sides, ru, rv, [=](float fu, float fv) {
    const float a = 2 * kPi * fu, b = 2 * kPi * fv;
    const float rr = R + r * std::cos(b);
    return Vec3{rr * std::sin(a), r * std::sin(b), rr * std::cos(a)};
  });
}

Mesh dome(float r, int seg, int rings) {
  // Seen from inside; the rim sits 0.1 r below the horizon so that no gap
  // shows between the ground's edge and the sky.
  return patch(
      "dome", seg, rings, 2, 1,
      [=](float fu, float fv) {
        const float a = 2 * kPi * fu, elev = 0.5f * kPi * fv;
        return Vec3{r * std::cos(elev) * std::sin(a), r * std::sin(elev) - 0.1f * r, r * std::cos(elev) * std::cos(a)};
      },
      /*inward=*/true);
}

Mesh crossed_quads(float w, float h, int count, uint64_t seed) {
  Mesh m;
  m.name = "foliage";
  Rng rng(seed);
  for (int q = 0; q < count; ++q) {
    const float a = kPi * float(q) / float(count) + rng.uniform(-0.2f, 0.2f);
    const float cx = std::cos(a) * w * 0.5f, cz = std::sin(a) * w * 0.5f;
    const float y0 = rng.uniform(0.0f, 0.3f) * h;
    const uint32_t base = uint32_t(m.vertices.size());
    const Vec3 p[4] = {{-cx, y0, -cz}, {cx, y0, cz}, {cx, y0 + h, cz}, {-cx, y0 + h, -cz}};
    const Vec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int i = 0; i < 4; ++i) {
      Vertex v;
      v.position = p[i];
      v.uv = uv[i];
      v.lm_uv = uv[i];
      m.vertices.push_back(v);
    }
    quad_indices(m, base, base + 1, base + 2, base + 3);
  }
  return m;
}

void append(Mesh& a, const Mesh& b, const Mat4& t) {
  const uint32_t base = uint32_t(a.vertices.size());
  for (Vertex v : b.vertices) {
    v.position = transform_point3(t, v.position);
    a.vertices.push_back(v);
  }
  for (uint32_t i : b.indices) a.indices.push_back(base + i);
}

// -------------------------------------------------------------- textures

static uint8_t to8(float x) { return uint8_t(std::clamp(x, 0.0f, 1.0f) * 255.0f + 0.5f); }

Texture texture_from(const std::string& name, int size, const TexelFn& fn, Wrap wrap, bool mipmapped) {
  std::vector<uint8_t> rgba(size_t(size) * size * 4);
  // Rows are independent: generated in parallel, identical for any thread count.
  parallel_for(size_t(size), 0, [&](size_t y) {
    for (int x = 0; x < size; ++x)
      fn((float(x) + 0.5f) / float(size), (float(y) + 0.5f) / float(size), &rgba[(y * size_t(size) + size_t(x)) * 4]);
  });
  return make_texture(name, "procedural:" + name, size, size, std::move(rgba), wrap, mipmapped);
}

static float lattice(int x, int y, int period, uint64_t seed) {
  x = ((x % period) + period) % period;
  y = ((y % period) + period) % period;
  return float(mix64(seed ^ (uint64_t(uint32_t(x)) << 32) ^ uint32_t(y)) >> 40) / 16777216.0f;
}

float noise(float u, float v, int period, uint64_t seed) {
  const float x = u * float(period), y = v * float(period);
  const float fx = std::floor(x), fy = std::floor(y);
  const int ix = int(fx), iy = int(fy);
  float tx = x - fx, ty = y - fy;
  tx = tx * tx * (3 - 2 * tx);
  ty = ty * ty * (3 - 2 * ty);
  const float a = lattice(ix, iy, period, seed), b = lattice(ix + 1, iy, period, seed);
  const float c = lattice(ix, iy + 1, period, seed), d = lattice(ix + 1, iy + 1, period, seed);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

float fbm(float u, float v, int period, int octaves, uint64_t seed) {
  float sum = 0, amp = 0.5f, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * noise(u, v, period << o, seed + uint64_t(o) * 7919);
    norm += amp;
    amp *= 0.5f;
  }
  return sum / norm;
}

static void put(uint8_t* p, float r, float g, float b, float a = 1) {
  p[0] = to8(r);
  p[1] = to8(g);
  p[2] = to8(b);
  p[3] = to8(a);
}

Texture stone(int size, uint64_t seed) {
  return texture_from("stone", size, [seed](float u, float v, uint8_t* p) {
    const float n = fbm(u, v, 4, 6, seed);
    const float vein = std::abs(noise(u, v, 8, seed + 3) - 0.5f) < 0.03f ? 0.8f : 1.0f;
    const float k = (0.45f + 0.4f * n) * vein;
    put(p, k * 1.02f, k * 0.98f, k * 0.9f);
  });
}

Texture cobbles(int size, uint64_t seed) {
  return texture_from("cobbles", size, [seed](float u, float v, uint8_t* p) {
    const int cells = 8;
    const float x = u * cells, y = v * cells;
    const float row = std::floor(y);
    const float xo = x + (int(row) % 2 ? 0.5f : 0.0f);
    const float fx = xo - std::floor(xo), fy = y - row;
    const float edge = std::min({fx, 1 - fx, fy, 1 - fy});
    const float n = fbm(u, v, 8, 4, seed);
    const float mortar = edge < 0.06f ? 0.45f : 1.0f;
    const float tint = lattice(int(std::floor(xo)), int(row), cells * 2, seed + 11);
    const float k = (0.4f + 0.35f * n + 0.15f * tint) * mortar;
    put(p, k * 0.95f, k * 0.9f, k * 0.85f);
  });
}

Texture brick(int size, uint64_t seed) {
  return texture_from("brick", size, [seed](float u, float v, uint8_t* p) {
    const float x = u * 4, y = v * 8;
    const float row = std::floor(y);
    const float xo = x + (int(row) % 2 ? 0.5f : 0.0f);
    const float fx = xo - std::floor(xo), fy = y - row;
    const bool mortar = fx < 0.04f || fy < 0.08f;
    const float n = fbm(u, v, 16, 3, seed);
    const float tint = lattice(int(std::floor(xo)), int(row), 8, seed + 5);
    if (mortar) put(p, 0.7f * (0.8f + 0.2f * n), 0.68f * (0.8f + 0.2f * n), 0.62f * (0.8f + 0.2f * n));
    else put(p, (0.55f + 0.2f * tint) * (0.8f + 0.3f * n), (0.25f + 0.08f * tint) * (0.8f + 0.3f * n), 0.18f * (0.8f + 0.3f * n));
  });
}

Texture wood(int size, uint64_t seed) {
  return texture_from("wood", size, [seed](float u, float v, uint8_t* p) {
    const float n = fbm(u, v, 4, 4, seed);
    const float rings = 0.5f + 0.5f * std::sin((u * 12 + n * 4) * 2 * kPi);
    const float plank = std::fmod(v * 4, 1.0f) < 0.03f ? 0.5f : 1.0f;
    const float k = (0.6f + 0.25f * rings) * plank;
    put(p, 0.62f * k, 0.42f * k, 0.22f * k);
  });
}

Texture marble(int size, uint64_t seed) {
  return texture_from("marble", size, [seed](float u, float v, uint8_t* p) {
    const float n = fbm(u, v, 4, 6, seed);
    const float veins = std::pow(std::abs(std::sin((u * 3 + v * 2 + n * 3) * kPi)), 0.3f);
    const float k = 0.55f + 0.4f * veins;
    put(p, k, k * 0.97f, k * 0.95f);
  });
}

Texture metal(int size, uint64_t seed) {
  return texture_from("bronze", size, [seed](float u, float v, uint8_t* p) {
    const float n = fbm(u, v, 8, 5, seed);
    const float streak = noise(u * 0.1f, v, 64, seed + 9);
    const float k = 0.5f + 0.3f * n + 0.2f * streak;
    put(p, 0.72f * k, 0.5f * k, 0.25f * k);
  });
}

Texture grass(int size, uint64_t seed) {
  return texture_from("grass", size, [seed](float u, float v, uint8_t* p) {
    const float n = fbm(u, v, 8, 6, seed);
    const float blades = noise(u, v, 128, seed + 1);
    put(p, 0.2f + 0.15f * n, 0.4f + 0.3f * n * blades + 0.1f * blades, 0.12f + 0.08f * n);
  });
}

Texture bark(int size, uint64_t seed) {
  return texture_from("bark", size, [seed](float u, float v, uint8_t* p) {
    const float n = fbm(u * 4, v, 4, 5, seed);
    const float ridges = 0.5f + 0.5f * std::sin((u * 16 + n * 2) * 2 * kPi);
    const float k = 0.3f + 0.3f * ridges * n;
    put(p, 0.45f * k + 0.05f, 0.33f * k + 0.03f, 0.2f * k);
  });
}

Texture leaves(int size, uint64_t seed) {
  return texture_from(
      "leaves", size,
      [seed](float u, float v, uint8_t* p) {
        // Blobs of leaves with holes between them: alpha is 0 or 1 before
        // filtering, so the alpha test cuts clean silhouettes.
        const float n = fbm(u, v, 8, 4, seed);
        const float crown = 1.0f - std::hypot(u - 0.5f, (v - 0.55f) * 1.2f) * 2.0f;
        const bool leaf = n + crown * 0.6f > 0.62f;
        const float shade = 0.5f + 0.5f * noise(u, v, 32, seed + 4);
        put(p, 0.12f * shade + 0.05f, 0.35f + 0.3f * shade, 0.08f, leaf ? 1.0f : 0.0f);
      },
      Wrap::clamp_to_edge);
}

Texture water(int size, uint64_t seed) {
  return texture_from("water", size, [seed](float u, float v, uint8_t* p) {
    const float n = fbm(u, v, 4, 5, seed);
    put(p, 0.12f + 0.1f * n, 0.3f + 0.2f * n, 0.45f + 0.25f * n);
  });
}

Texture sky(int size, uint64_t seed) {
  return texture_from("sky", size, [seed](float u, float v, uint8_t* p) {
    const float cloud = std::clamp((fbm(u, v * 0.5f, 4, 5, seed) - 0.5f) * 3.0f, 0.0f, 1.0f) * (1.0f - v);
    const float r = 0.55f - 0.3f * v, g = 0.7f - 0.25f * v, b = 0.95f - 0.1f * v;
    put(p, r + (0.95f - r) * cloud, g + (0.95f - g) * cloud, b + (0.97f - b) * cloud);
  });
}

Texture cloth(int size, uint64_t seed, uint8_t r, uint8_t g, uint8_t b) {
  const std::string name = "cloth-" + std::to_string(r) + "-" + std::to_string(g) + "-" + std::to_string(b);
  return texture_from(name, size, [=](float u, float v, uint8_t* p) {
    const float weave = 0.85f + 0.15f * (std::sin(u * size * 0.8f) * std::sin(v * size * 0.8f));
    const float n = 0.8f + 0.2f * fbm(u, v, 4, 3, seed);
    const bool stripe = std::fmod(v * 6, 1.0f) < 0.15f;
    const bool emblem = std::hypot(u - 0.5f, v - 0.6f) < 0.18f;
    float k = weave * n * (stripe ? 0.6f : 1.0f);
    if (emblem) put(p, 0.9f * n, 0.8f * n, 0.3f * n);
    else put(p, r / 255.0f * k, g / 255.0f * k, b / 255.0f * k);
  });
}

Texture fabric_person(int size, uint64_t seed, uint8_t r, uint8_t g, uint8_t b) {
  const std::string name = "person-" + std::to_string(r) + "-" + std::to_string(g) + "-" + std::to_string(b);
  return texture_from(name, size, [=](float u, float v, uint8_t* p) {
    // Lower 70% of v: clothing; upper 30%: skin and hair (the head's part).
    const float n = 0.8f + 0.2f * fbm(u, v, 8, 3, seed);
    if (v < 0.35f) put(p, 0.2f * n, 0.22f * n, 0.3f * n);  // trousers
    else if (v < 0.7f) put(p, r / 255.0f * n, g / 255.0f * n, b / 255.0f * n);
    else if (v < 0.9f) put(p, 0.85f * n, 0.65f * n, 0.5f * n);
    else put(p, 0.25f * n, 0.17f * n, 0.1f * n);
  });
}

// --------------------------------------------------------------- builder

SceneBuilder::SceneBuilder(std::string name, std::string description) {
  m_scene.name = std::move(name);
  m_scene.description = std::move(description);
}

int SceneBuilder::texture(Texture t) {
  m_scene.textures.push_back(std::move(t));
  return int(m_scene.textures.size()) - 1;
}

int SceneBuilder::material(Material m) {
  m_scene.materials.push_back(std::move(m));
  return int(m_scene.materials.size()) - 1;
}

int SceneBuilder::mesh(Mesh m) {
  m_scene.meshes.push_back(std::move(m));
  return int(m_scene.meshes.size()) - 1;
}

int SceneBuilder::object(const std::string& name, int mesh_, int material_, const Mat4& t) {
  m_scene.objects.push_back(Object::of(name, mesh_, material_, t));
  return int(m_scene.objects.size()) - 1;
}

Scene SceneBuilder::take() {
  m_scene.validate();
  return std::move(m_scene);
}

}  // namespace oovr::procedural
