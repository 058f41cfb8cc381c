#include "oovr/scene/formats/ac3d.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/limits.h"
#include "oovr/scene/load.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxDepth = 256;

class Ac3dParser {
 public:
  Ac3dParser(const std::string& text, const std::string& name, const Ac3dOptions& options) : m_name(name), m_options(options) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      m_lines.push_back(std::move(line));
    }
    if (m_options.texture_dirs.empty()) m_options.texture_dirs.push_back(fs::path(name).parent_path().string());
  }

  Scene parse() {
    if (m_lines.empty() || m_lines[0].rfind("AC3D", 0) != 0) throw fail("not an AC3D file (no AC3D header)", 0);
    m_scene.name = fs::path(m_name).stem().string();
    m_scene.description = "AC3D file " + m_name;
    m_line = 1;
    while (m_line < m_lines.size()) {
      const auto t = tokens(m_lines[m_line]);
      if (t.empty()) {
        ++m_line;
      } else if (t[0] == "MATERIAL") {
        material(t);
        ++m_line;
      } else if (t[0] == "OBJECT") {
        object(Mat4::identity(), 0);
      } else {
        throw fail("unexpected '" + t[0] + "' at top level", m_line);
      }
    }
    if (m_scene.objects.empty()) throw fail("the file has no polygons", m_line);
    return std::move(m_scene);
  }

 private:
  Error fail(const std::string& what, size_t line) const {
    return Error("bad AC3D file '" + m_name + "' line " + std::to_string(line + 1) + ": " + what);
  }

  // Whitespace-separated tokens; quoted strings are one token (without quotes).
  static std::vector<std::string> tokens(const std::string& s) {
    std::vector<std::string> t;
    size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
      if (i >= s.size()) break;
      if (s[i] == '"') {
        const size_t end = s.find('"', i + 1);
        t.push_back(s.substr(i + 1, (end == std::string::npos ? s.size() : end) - i - 1));
        i = end == std::string::npos ? s.size() : end + 1;
      } else {
        const size_t start = i;
        while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        t.push_back(s.substr(start, i - start));
      }
    }
    return t;
  }

  float number(const std::vector<std::string>& t, size_t k, size_t line) const {
    if (k >= t.size()) throw fail("missing number", line);
    const std::string& s = t[k];
    float v = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) throw fail("'" + s + "' is not a number", line);
    return v;
  }

  long integer(const std::vector<std::string>& t, size_t k, size_t line, long max) const {
    if (k >= t.size()) throw fail("missing count", line);
    const std::string& s = t[k];
    long v = 0;
    const char* b = s.data();
    const bool hex = s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
    const auto r = std::from_chars(b + (hex ? 2 : 0), b + s.size(), v, hex ? 16 : 10);
    if (r.ec != std::errc() || r.ptr != b + s.size() || v < 0) throw fail("'" + s + "' is not a count", line);
    if (v > max) throw fail("count " + s + " exceeds what the rest of the file can hold", line);
    return v;
  }

  void material(const std::vector<std::string>& t) {
    Vec4 c{1, 1, 1, 1};
    for (size_t k = 1; k < t.size(); ++k) {
      if (t[k] == "rgb" && k + 3 < t.size())
        c = {number(t, k + 1, m_line), number(t, k + 2, m_line), number(t, k + 3, m_line), c.w};
      if (t[k] == "trans" && k + 1 < t.size()) c.w = 1.0f - number(t, k + 1, m_line);
    }
    m_material_colours.push_back(c);
  }

  void object(const Mat4& parent, int depth) {
    if (depth > kMaxDepth) throw fail("objects nested more than 256 deep", m_line);
    const size_t start_line = m_line;
    const auto header = tokens(m_lines[m_line++]);
    const std::string type = header.size() > 1 ? header[1] : "";
    std::string name = type;
    std::string texture;
    bool texture_seen = false;
    float rep_u = 1, rep_v = 1, off_u = 0, off_v = 0;
    Vec3 loc;
    Mat4 rot;
    std::vector<Vec3> verts;
    struct Surf {
      int mat;
      bool two_sided;
      bool strip;
      std::vector<std::pair<uint32_t, Vec2>> refs;
    };
    std::vector<Surf> surfs;
    long kids = -1;
    while (m_line < m_lines.size() && kids < 0) {
      const size_t here = m_line;
      const auto t = tokens(m_lines[m_line++]);
      if (t.empty()) continue;
      const std::string& k = t[0];
      const long remaining = long(m_lines.size() - m_line);
      if (k == "name" && t.size() > 1) {
        name = t[1];
      } else if (k == "data") {
        // data <bytes>, then the bytes on the following line(s)
        long bytes = integer(t, 1, here, 1L << 30);
        while (bytes > 0 && m_line < m_lines.size()) bytes -= long(m_lines[m_line++].size()) + 1;
      } else if (k == "texture") {
        // TORCS lists base, tiled, skids and shad textures; the first is drawn.
        if (!texture_seen && t.size() > 1 && t[1] != "empty_texture_no_mapping") texture = t[1];
        texture_seen = true;
      } else if (k == "texrep") {
        rep_u = number(t, 1, here);
        rep_v = number(t, 2, here);
      } else if (k == "texoff") {
        off_u = number(t, 1, here);
        off_v = number(t, 2, here);
      } else if (k == "loc") {
        loc = {number(t, 1, here), number(t, 2, here), number(t, 3, here)};
      } else if (k == "rot") {
        // Nine numbers, row by row.
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) rot.at(r, c) = number(t, size_t(1 + r * 3 + c), here);
      } else if (k == "numvert") {
        const long n = integer(t, 1, here, remaining);
        verts.reserve(size_t(n));
        for (long v = 0; v < n; ++v) {
          const size_t l = m_line;
          const auto vt = tokens(m_lines[m_line++]);
          verts.push_back({number(vt, 0, l), number(vt, 1, l), number(vt, 2, l)});
        }
      } else if (k == "numsurf") {
        const long n = integer(t, 1, here, remaining);
        for (long s = 0; s < n; ++s) {
          Surf surf{0, false, false, {}};
          long flags = 0;
          for (;;) {
            if (m_line >= m_lines.size()) throw fail("surface " + std::to_string(s) + " ends early", m_line);
            const size_t l = m_line;
            const auto st = tokens(m_lines[m_line++]);
            if (st.empty()) continue;
            if (st[0] == "SURF") {
              flags = integer(st, 1, l, 0xffff);
            } else if (st[0] == "mat") {
              surf.mat = int(integer(st, 1, l, 1 << 20));
            } else if (st[0] == "refs") {
              const long nr = integer(st, 1, l, long(m_lines.size() - m_line));
              for (long r = 0; r < nr; ++r) {
                const size_t rl = m_line;
                const auto rt = tokens(m_lines[m_line++]);
                const long idx = integer(rt, 0, rl, 1L << 30);
                surf.refs.push_back({uint32_t(idx), Vec2{number(rt, 1, rl), number(rt, 2, rl)}});
              }
              break;
            } else {
              throw fail("unexpected '" + st[0] + "' in a surface", l);
            }
          }
          surf.two_sided = (flags & 0x20) != 0;
          // Type in the low bits: 0 polygon, 1 closed line, 2 line, and
          // TORCS's 4, a triangle strip. Lines are not drawn.
          surf.strip = (flags & 0xf) == 4;
          if ((flags & 0xf) == 0 || surf.strip) surfs.push_back(std::move(surf));
        }
      } else if (k == "kids") {
        kids = integer(t, 1, here, remaining);
      } else if (k == "crease" || k == "url" || k == "subdiv" || k == "hidden" || k == "locked" || k == "folded" ||
                 k == "shader") {
        // no bearing on what is drawn
      } else {
        throw fail("unexpected '" + k + "' in object '" + name + "'", here);
      }
    }
    if (kids < 0) throw fail("object '" + name + "' has no kids line", start_line);
    const Mat4 world = parent * translate(loc) * rot;
    if (type == "poly" && !surfs.empty()) emit(name, world, verts, surfs, texture, rep_u, rep_v, off_u, off_v, start_line);
    for (long c = 0; c < kids; ++c) {
      while (m_line < m_lines.size() && tokens(m_lines[m_line]).empty()) ++m_line;
      if (m_line >= m_lines.size()) {
        // TORCS's track generator declares more kids than it writes; its
        // loader stops at the end of the file, and so does this one.
        m_short_kids.push_back("object '" + name + "' declares " + std::to_string(kids) + " kids, the file holds " +
                               std::to_string(c));
        break;
      }
      if (tokens(m_lines[m_line])[0] != "OBJECT")
        throw fail("object '" + name + "' expects " + std::to_string(kids) + " kids, not '" + m_lines[m_line] + "'", m_line);
      object(world, depth + 1);
    }
  }

  template <class Surfs>
  void emit(const std::string& name, const Mat4& world, const std::vector<Vec3>& verts, const Surfs& surfs,
            const std::string& texture, float rep_u, float rep_v, float off_u, float off_v, size_t line) {
    Mesh mesh;
    mesh.name = name;
    bool two_sided = false;
    for (const auto& s : surfs) {
      if (s.refs.size() < 3) continue;
      two_sided = two_sided || s.two_sided;
      const uint32_t base = uint32_t(mesh.vertices.size());
      for (const auto& [idx, uv] : s.refs) {
        if (idx >= verts.size())
          throw fail("object '" + name + "' refers to vertex " + std::to_string(idx) + " of " + std::to_string(verts.size()),
                     line);
        Vertex v;
        v.position = transform_point3(world, verts[idx]);
        v.uv = {uv.x * rep_u + off_u, uv.y * rep_v + off_v};
        mesh.vertices.push_back(v);
      }
      // AC3D polygons are counter-clockwise seen from the front; fans
      // triangulate the (convex) polygons TORCS writes. Strips alternate
      // their winding so that every triangle faces the same way.
      if (s.strip) {
        for (uint32_t k = 0; k + 2 < s.refs.size(); ++k) {
          if (k % 2 == 0) mesh.indices.insert(mesh.indices.end(), {base + k, base + k + 1, base + k + 2});
          else mesh.indices.insert(mesh.indices.end(), {base + k + 1, base + k, base + k + 2});
        }
      } else {
        for (uint32_t k = 1; k + 1 < s.refs.size(); ++k) mesh.indices.insert(mesh.indices.end(), {base, base + k, base + k + 1});
      }
    }
    if (mesh.indices.empty()) return;
    Material m = Material::textured(texture.empty() ? "untextured" : texture, texture.empty() ? -1 : texture_index(texture));
    m.two_sided = two_sided;
    const int mat = surfs.front().mat;
    if (!texture.empty()) {
      // Images with transparent texels (foliage, fences) are cut out with
      // the alpha test, as TORCS draws them.
      if (m_has_alpha[size_t(m.pass().layers[0].texture)]) m.pass().alpha_func = AlphaFunc::gequal;
    } else if (mat >= 0 && size_t(mat) < m_material_colours.size()) {
      m.pass().colour = m_material_colours[size_t(mat)];
    }
    m_scene.meshes.push_back(std::move(mesh));
    m_scene.materials.push_back(m);
    m_scene.objects.push_back(
        Object::of(name, int(m_scene.meshes.size()) - 1, int(m_scene.materials.size()) - 1, Mat4::identity()));
  }

  int texture_index(const std::string& file) {
    if (const auto it = m_texture_of.find(file); it != m_texture_of.end()) return it->second;
    std::string found;
    std::error_code ec;
    for (const auto& dir : m_options.texture_dirs) {
      const fs::path p = fs::path(dir) / file;
      if (fs::is_regular_file(p, ec)) {
        found = p.string();
        break;
      }
    }
    int id;
    if (found.empty()) {
      m_missing.push_back(file);
      if (m_missing_texture < 0) {
        std::vector<uint8_t> px(16 * 16 * 4, 255);
        for (size_t i = 0; i < px.size(); i += 4) px[i + 1] = 0;  // magenta
        m_scene.textures.push_back(make_texture("missing", "oovr:missing", 16, 16, std::move(px)));
        m_missing_texture = int(m_scene.textures.size()) - 1;
        m_has_alpha.resize(size_t(m_missing_texture) + 1, false);
      }
      id = m_missing_texture;
    } else {
      MipLevel base = load_image_file(found);
      bool alpha = false;
      for (size_t i = 3; i < base.rgba.size() && !alpha; i += 4) alpha = base.rgba[i] < 255;
      m_scene.textures.push_back(
          make_texture(file, fs::weakly_canonical(found, ec).string(), base.width, base.height, std::move(base.rgba)));
      id = int(m_scene.textures.size()) - 1;
      m_has_alpha.resize(size_t(id) + 1, false);
      m_has_alpha[size_t(id)] = alpha;
    }
    return m_texture_of[file] = id;
  }

 public:
  std::vector<std::string> missing() const { return m_missing; }
  std::vector<std::string> short_kids() const { return m_short_kids; }

 private:
  std::string m_name;
  Ac3dOptions m_options;
  std::vector<std::string> m_lines;
  size_t m_line = 0;
  Scene m_scene;
  std::vector<Vec4> m_material_colours;
  std::map<std::string, int> m_texture_of;
  std::vector<bool> m_has_alpha;  // per texture: any texel not opaque
  int m_missing_texture = -1;
  std::vector<std::string> m_missing;
  std::vector<std::string> m_short_kids;
};

}  // namespace

Scene parse_ac3d(const std::string& text, const std::string& name, const Ac3dOptions& options) {
  Ac3dParser p(text, name, options);
  Scene s = p.parse();
  for (const auto& n : p.short_kids()) s.notes.push_back(n);
  const auto missing = p.missing();
  if (!missing.empty()) {
    std::string names;
    for (size_t k = 0; k < missing.size() && k < 8; ++k) names += (k ? ", " : "") + missing[k];
    if (missing.size() > 8) names += ", ...";
    s.notes.push_back(std::to_string(missing.size()) + " textures not found, shown as 'missing': " + names);
  }
  return s;
}

Scene load_ac3d_file(const std::string& path, const Ac3dOptions& options) {
  return parse_ac3d(read_input_file(path, "AC3D file", InputLimits::get().file_bytes), path, options);
}

}  // namespace oovr
