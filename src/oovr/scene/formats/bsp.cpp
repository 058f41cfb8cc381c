#include "oovr/scene/formats/bsp.h"

#include <cmath>
#include <cstring>

#include "oovr/core/error.h"

namespace oovr {
namespace {

constexpr int kLumps = 17;
enum Lump { kEntities = 0, kTextures = 1, kVertexes = 10, kMeshverts = 11, kFaces = 13, kLightmaps = 14 };
constexpr size_t kTextureBytes = 72, kVertexBytes = 44, kFaceBytes = 104;
constexpr size_t kLightmapBytes = size_t(kBspLightmapSize) * kBspLightmapSize * 3;

int32_t i32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);  // little endian, as the format and x86-64
  return int32_t(v);
}
float f32(const uint8_t* p) {
  float v;
  std::memcpy(&v, p, 4);
  return v;
}
Vec3 vec3(const uint8_t* p) { return {f32(p), f32(p + 4), f32(p + 8)}; }
bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct LumpView {
  const uint8_t* data;
  size_t size;
};

}  // namespace

BspMap parse_bsp(const uint8_t* data, size_t size, const std::string& name) {
  const auto fail = [&](const std::string& why) { return Error("bad BSP file '" + name + "': " + why); };
  const size_t header = 8 + kLumps * 8;
  if (size < header) throw fail("file is " + std::to_string(size) + " bytes, shorter than the header");
  if (std::memcmp(data, "IBSP", 4) != 0) throw fail("not an IBSP file (bad magic)");
  if (const int32_t v = i32(data + 4); v != 46) throw fail("version " + std::to_string(v) + " is not Quake 3's 46");
  LumpView lumps[kLumps];
  for (int l = 0; l < kLumps; ++l) {
    const int64_t off = i32(data + 8 + l * 8), len = i32(data + 12 + l * 8);
    if (off < 0 || len < 0 || uint64_t(off) + uint64_t(len) > size)
      throw fail("lump " + std::to_string(l) + " (offset " + std::to_string(off) + ", length " + std::to_string(len) +
                 ") lies outside the " + std::to_string(size) + "-byte file");
    lumps[l] = {data + off, size_t(len)};
  }
  auto count = [&](int lump, size_t element, const char* what) {
    if (lumps[lump].size % element != 0)
      throw fail(std::string(what) + " lump length " + std::to_string(lumps[lump].size) + " is not a multiple of " +
                 std::to_string(element));
    return lumps[lump].size / element;
  };

  BspMap m;
  const size_t n_textures = count(kTextures, kTextureBytes, "texture");
  m.shaders.resize(n_textures);
  for (size_t i = 0; i < n_textures; ++i) {
    const uint8_t* p = lumps[kTextures].data + i * kTextureBytes;
    const char* s = reinterpret_cast<const char*>(p);
    m.shaders[i].name.assign(s, strnlen(s, 64));
    m.shaders[i].surface_flags = i32(p + 64);
    m.shaders[i].contents = i32(p + 68);
  }

  const size_t n_vertices = count(kVertexes, kVertexBytes, "vertex");
  m.vertices.resize(n_vertices);
  for (size_t i = 0; i < n_vertices; ++i) {
    const uint8_t* p = lumps[kVertexes].data + i * kVertexBytes;
    BspVertex& v = m.vertices[i];
    v.position = vec3(p);
    v.st = {f32(p + 12), f32(p + 16)};
    v.lm = {f32(p + 20), f32(p + 24)};
    v.normal = vec3(p + 28);
    if (!finite(v.position)) throw fail("vertex " + std::to_string(i) + " has a position that is not a finite number");
    // Some compilers leave NaN lightmap coordinates on vertex-lit surfaces,
    // which never read them (am_underworks2 has 26); they become 0.
    for (float* c : {&v.st.x, &v.st.y, &v.lm.x, &v.lm.y})
      if (!std::isfinite(*c)) {
        *c = 0;
        ++m.repaired_coordinates;
      }
    if (!finite(v.normal)) v.normal = {0, 0, 0};
  }

  const size_t n_meshverts = count(kMeshverts, 4, "meshvert");
  m.meshverts.resize(n_meshverts);
  for (size_t i = 0; i < n_meshverts; ++i) m.meshverts[i] = i32(lumps[kMeshverts].data + i * 4);

  m.lightmap_count = int(count(kLightmaps, kLightmapBytes, "lightmap"));
  m.lightmaps.assign(lumps[kLightmaps].data, lumps[kLightmaps].data + lumps[kLightmaps].size);

  const size_t n_faces = count(kFaces, kFaceBytes, "face");
  m.faces.resize(n_faces);
  for (size_t i = 0; i < n_faces; ++i) {
    const uint8_t* p = lumps[kFaces].data + i * kFaceBytes;
    BspFace& f = m.faces[i];
    f.shader = i32(p);
    f.type = i32(p + 8);
    f.first_vertex = i32(p + 12);
    f.vertex_count = i32(p + 16);
    f.first_meshvert = i32(p + 20);
    f.meshvert_count = i32(p + 24);
    f.lightmap = i32(p + 28);
    f.normal = vec3(p + 84);
    f.patch_w = i32(p + 96);
    f.patch_h = i32(p + 100);
    const std::string face = "face " + std::to_string(i);
    if (f.shader < 0 || size_t(f.shader) >= n_textures)
      throw fail(face + " names shader " + std::to_string(f.shader) + " of " + std::to_string(n_textures));
    if (f.type < kBspPolygon || f.type > kBspBillboard) throw fail(face + " has unknown type " + std::to_string(f.type));
    if (f.type == kBspBillboard) continue;  // not drawn; nothing else is read
    if (f.first_vertex < 0 || f.vertex_count < 0 || uint64_t(f.first_vertex) + uint64_t(f.vertex_count) > n_vertices)
      throw fail(face + " has vertices outside the vertex lump");
    // A lightmap index past the lightmap lump is left to the loader: maps
    // compiled with q3map2 -external keep their lightmaps in image files.
    if (!finite(f.normal)) f.normal = {0, 0, 0};
    if (f.type == kBspPatch) {
      if (f.patch_w < 3 || f.patch_h < 3 || f.patch_w % 2 == 0 || f.patch_h % 2 == 0 ||
          int64_t(f.patch_w) * f.patch_h != f.vertex_count)
        throw fail(face + " is a patch with a bad control grid " + std::to_string(f.patch_w) + "x" + std::to_string(f.patch_h) +
                   " for " + std::to_string(f.vertex_count) + " vertices");
    } else {
      if (f.first_meshvert < 0 || f.meshvert_count < 0 || uint64_t(f.first_meshvert) + uint64_t(f.meshvert_count) > n_meshverts)
        throw fail(face + " has indices outside the meshvert lump");
      if (f.meshvert_count % 3 != 0) throw fail(face + " has an index count that is not a multiple of 3");
      for (int k = 0; k < f.meshvert_count; ++k) {
        const int32_t mv = m.meshverts[size_t(f.first_meshvert + k)];
        if (mv < 0 || mv >= f.vertex_count) throw fail(face + " has an index past its vertices");
      }
    }
  }

  std::string entities(reinterpret_cast<const char*>(lumps[kEntities].data), lumps[kEntities].size);
  if (const auto nul = entities.find('\0'); nul != std::string::npos) entities.resize(nul);
  m.entities = parse_bsp_entities(entities, name);
  return m;
}

std::vector<BspEntity> parse_bsp_entities(const std::string& text, const std::string& name) {
  std::vector<BspEntity> out;
  size_t i = 0;
  auto skip_space = [&] {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  };
  auto quoted = [&]() -> std::string {
    if (i >= text.size() || text[i] != '"')
      throw Error("bad BSP file '" + name + "': entity lump expects a quoted string at byte " + std::to_string(i));
    const size_t end = text.find('"', i + 1);
    if (end == std::string::npos) throw Error("bad BSP file '" + name + "': unterminated string in the entity lump");
    std::string s = text.substr(i + 1, end - i - 1);
    i = end + 1;
    return s;
  };
  for (;;) {
    skip_space();
    if (i >= text.size()) break;
    if (text[i] != '{') throw Error("bad BSP file '" + name + "': entity lump expects '{' at byte " + std::to_string(i));
    ++i;
    BspEntity e;
    for (;;) {
      skip_space();
      if (i >= text.size()) throw Error("bad BSP file '" + name + "': entity not closed before the end of the lump");
      if (text[i] == '}') {
        ++i;
        break;
      }
      std::string key = quoted();
      skip_space();
      e[key] = quoted();
    }
    out.push_back(std::move(e));
  }
  return out;
}

namespace {

BspVertex mix3(const BspVertex& a, const BspVertex& b, const BspVertex& c, float t) {
  // Quadratic Bezier: (1-t)^2 a + 2t(1-t) b + t^2 c.
  const float wa = (1 - t) * (1 - t), wb = 2 * t * (1 - t), wc = t * t;
  BspVertex r;
  r.position = a.position * wa + b.position * wb + c.position * wc;
  r.normal = a.normal * wa + b.normal * wb + c.normal * wc;
  r.st = {a.st.x * wa + b.st.x * wb + c.st.x * wc, a.st.y * wa + b.st.y * wb + c.st.y * wc};
  r.lm = {a.lm.x * wa + b.lm.x * wb + c.lm.x * wc, a.lm.y * wa + b.lm.y * wb + c.lm.y * wc};
  return r;
}

// Appends triangle (a, b, c) so that it faces the way its vertex normals
// point; with no usable normals, the given order is kept.
void add_oriented(std::vector<BspVertex>& v, std::vector<uint32_t>& idx, uint32_t a, uint32_t b, uint32_t c) {
  const Vec3 g = cross(v[b].position - v[a].position, v[c].position - v[a].position);
  const Vec3 n = v[a].normal + v[b].normal + v[c].normal;
  if (dot(g, n) < 0) std::swap(b, c);
  idx.insert(idx.end(), {a, b, c});
}

}  // namespace

void bsp_face_triangles(const BspMap& map, const BspFace& f, int level, std::vector<BspVertex>& vertices,
                        std::vector<uint32_t>& indices) {
  if (f.type == kBspPolygon || f.type == kBspMesh) {
    const uint32_t base = uint32_t(vertices.size());
    vertices.insert(vertices.end(), map.vertices.begin() + f.first_vertex,
                    map.vertices.begin() + f.first_vertex + f.vertex_count);
    // Quake 3 lists triangles clockwise seen from the front; reverse them.
    for (int k = 0; k + 2 < f.meshvert_count; k += 3) {
      const int32_t* mv = &map.meshverts[size_t(f.first_meshvert + k)];
      indices.insert(indices.end(), {base + uint32_t(mv[0]), base + uint32_t(mv[2]), base + uint32_t(mv[1])});
    }
    return;
  }
  if (f.type != kBspPatch) return;
  if (level < 1) level = 1;
  if (level > kMaxTessellation) level = kMaxTessellation;
  const BspVertex* grid = &map.vertices[size_t(f.first_vertex)];
  const int w = f.patch_w;
  const int n = level + 1;
  std::vector<BspVertex> column(3);
  for (int py = 0; py + 2 < f.patch_h; py += 2)
    for (int px = 0; px + 2 < w; px += 2) {
      const uint32_t base = uint32_t(vertices.size());
      for (int j = 0; j < n; ++j) {
        const float v = float(j) / float(level);
        for (int c = 0; c < 3; ++c)
          column[size_t(c)] = mix3(grid[py * w + px + c], grid[(py + 1) * w + px + c], grid[(py + 2) * w + px + c], v);
        for (int i = 0; i < n; ++i) vertices.push_back(mix3(column[0], column[1], column[2], float(i) / float(level)));
      }
      for (int j = 0; j < level; ++j)
        for (int i = 0; i < level; ++i) {
          const uint32_t a = base + uint32_t(j * n + i), b = a + 1, c = a + uint32_t(n) + 1, d = a + uint32_t(n);
          add_oriented(vertices, indices, a, b, c);
          add_oriented(vertices, indices, a, c, d);
        }
    }
}

}  // namespace oovr
