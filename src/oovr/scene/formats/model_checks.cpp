#include "oovr/scene/formats/model_checks.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <vector>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/limits.h"
#include "oovr/core/text.h"
#include "oovr/core/units.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void bad(const std::string& name, const std::string& why) { throw Error("cannot load '" + name + "': " + why); }

int ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

// PLY (Turk 1994): an ASCII header of elements and their properties, then
// the records. oovr reads it itself (assimp trusted the header's counts,
// looped for ever on a header whose end_header ended a property's name, and
// aborted on faces its triangulation did not expect): every declared record
// and list item must be in the file; the vertices' x, y, z (and s, t or u,
// v) and the faces' index lists are kept.
enum class PlyKind { signed_int, unsigned_int, real };
struct PlyProperty {
  std::string name;
  bool list = false;
  int count_size = 0;  // bytes of a list's count (binary)
  int size = 0;        // bytes of a value or a list item (binary)
  PlyKind kind = PlyKind::real;
};
struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

PlyKind ply_kind(const std::string& t) {
  if (t == "float" || t == "float32" || t == "double" || t == "float64") return PlyKind::real;
  if (t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32") return PlyKind::signed_int;
  return PlyKind::unsigned_int;
}

PlyMesh parse_ply(const std::string& bytes, const std::string& name) {
  if (bytes.compare(0, 4, "ply\n") != 0 && bytes.compare(0, 5, "ply\r\n") != 0) bad(name, "not a PLY file (no 'ply' magic)");
  // The header ends at a line that is "end_header" alone.
  size_t end = std::string::npos, newline = std::string::npos;
  for (size_t at = bytes.find('\n'); at != std::string::npos; at = bytes.find('\n', at + 1)) {
    const size_t next = bytes.find('\n', at + 1);
    std::string_view line = std::string_view(bytes).substr(at + 1, (next == std::string::npos ? bytes.size() : next) - at - 1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    if (line == "end_header") {
      end = at + 1;
      newline = next;
      break;
    }
  }
  if (end == std::string::npos) bad(name, "the PLY header has no end_header line");
  if (newline == std::string::npos) bad(name, "the PLY file ends after its header");
  std::istringstream header(bytes.substr(0, end));
  std::string line, format;
  std::vector<PlyElement> elements;
  uint64_t total = 0;
  const InputLimits& lim = InputLimits::get();
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string w;
    words >> w;
    if (w == "format") {
      words >> format;
    } else if (w == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      if (!words) bad(name, "a PLY element without a count: '" + printable(line) + "'");
      total += e.count;
      check_limit(total, lim.elements, "elements", "model '" + name + "'", "PLY records declared");
      elements.push_back(e);
    } else if (w == "property") {
      if (elements.empty()) bad(name, "a PLY property before any element");
      PlyProperty p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type;
        p.list = true;
        p.count_size = ply_type_size(count_type);
        p.size = ply_type_size(item_type);
        p.kind = ply_kind(item_type);
        if (!p.count_size || !p.size || ply_kind(count_type) == PlyKind::real)
          bad(name, "unknown PLY list types in '" + printable(line) + "'");
      } else {
        p.size = ply_type_size(type);
        p.kind = ply_kind(type);
        if (!p.size) bad(name, "unknown PLY property type '" + printable(type) + "'");
      }
      words >> p.name;
      elements.back().properties.push_back(p);
    }  // other lines (comments, and the free text some exporters write) say nothing of the records
  }
  const bool ascii = format == "ascii", little = format == "binary_little_endian";
  if (!ascii && !little && format != "binary_big_endian") bad(name, "unknown PLY format '" + printable(format) + "'");
  const auto truncated = [&](const std::string& what) { bad(name, "the PLY file ends inside its " + what + " (truncated?)"); };
  size_t at = newline + 1;
  // The next value, as a double (counts and indices are checked whole).
  const auto value = [&](int size, PlyKind kind, const std::string& what) -> double {
    if (ascii) {
      while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
      if (at >= bytes.size()) truncated(what);
      const size_t begin = at;
      while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
      double v = 0;
      const auto [ptr, ec] = std::from_chars(bytes.data() + begin, bytes.data() + at, v);
      if (ec != std::errc() || ptr != bytes.data() + at)
        bad(name, "a PLY value that is not a number: '" + printable(bytes.substr(begin, std::min<size_t>(at - begin, 40))) + "'");
      return v;
    }
    if (bytes.size() - at < size_t(size)) truncated(what);
    uint64_t raw = 0;
    for (int i = 0; i < size; ++i) raw = (raw << 8) | uint8_t(bytes[at + size_t(little ? size - 1 - i : i)]);
    at += size_t(size);
    if (kind == PlyKind::real) {
      if (size == 4) {
        const uint32_t r32 = uint32_t(raw);
        float f;
        std::memcpy(&f, &r32, 4);
        return double(f);
      }
      double d;
      std::memcpy(&d, &raw, 8);
      return d;
    }
    if (kind == PlyKind::signed_int && size < 8 && (raw >> (size * 8 - 1)) & 1)
      return double(int64_t(raw) - (int64_t(1) << (size * 8)));
    return double(raw);
  };
  PlyMesh mesh;
  uint64_t vertices = 0;
  for (size_t e = 0; e < elements.size(); ++e) {
    const PlyElement& el = elements[e];
    // A record without properties takes no bytes: nothing to walk (and
    // walking 10^8 of them took over 10 s, fuzzing found).
    if (el.properties.empty()) continue;
    const std::string what = "element " + std::to_string(e) + "'s records";
    const bool is_vertex = el.name == "vertex" && vertices == 0, is_face = el.name == "face";
    int ix = -1, iy = -1, iz = -1, iu = -1, iv = -1, ifaces = -1;
    for (size_t k = 0; k < el.properties.size(); ++k) {
      const std::string& n = el.properties[k].name;
      if (el.properties[k].list) {
        if (n == "vertex_indices" || n == "vertex_index") ifaces = int(k);
        continue;
      }
      if (n == "x") ix = int(k);
      else if (n == "y") iy = int(k);
      else if (n == "z") iz = int(k);
      else if (n == "s" || n == "u" || n == "texture_u") iu = int(k);
      else if (n == "t" || n == "v" || n == "texture_v") iv = int(k);
    }
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0)) bad(name, "the PLY vertices have no x, y and z");
    std::vector<double> v(el.properties.size());
    std::vector<uint32_t> face;
    for (uint64_t r = 0; r < el.count; ++r) {
      for (size_t k = 0; k < el.properties.size(); ++k) {
        const PlyProperty& p = el.properties[k];
        if (!p.list) {
          v[k] = value(p.size, p.kind, what);
          continue;
        }
        const double count = value(p.count_size, PlyKind::unsigned_int, what);
        if (!(count >= 0 && count <= double(uint64_t(1) << 32) && count == std::floor(count)))
          bad(name, "a bad PLY list length " + format_number(count));
        const uint64_t n = uint64_t(count);
        if (!ascii && n > (bytes.size() - at) / size_t(p.size)) truncated(what);
        const bool keep = is_face && int(k) == ifaces;
        if (keep) face.clear();
        for (uint64_t i = 0; i < n; ++i) {
          const double x = value(p.size, p.kind, what);
          if (!keep) continue;
          if (!(x >= 0 && x < double(vertices) && x == std::floor(x)))
            bad(name, "a PLY face names vertex " + format_number(x) + " of " + std::to_string(vertices));
          face.push_back(uint32_t(x));
        }
        // A polygon is a fan around its first corner; fewer than three
        // corners draw nothing.
        if (keep)
          for (size_t i = 2; i < face.size(); ++i) {
            if (mesh.indices.size() + 3 > lim.elements)
              exceeded_limit(lim.elements, "elements", "model '" + name + "'", "PLY indices");
            mesh.indices.insert(mesh.indices.end(), {face[0], face[i - 1], face[i]});
          }
      }
      if (is_vertex) {
        mesh.positions.push_back({float(v[size_t(ix)]), float(v[size_t(iy)]), float(v[size_t(iz)])});
        mesh.uvs.push_back({iu >= 0 ? float(v[size_t(iu)]) : 0.0f, iv >= 0 ? float(v[size_t(iv)]) : 0.0f});
      }
    }
    if (is_vertex) vertices = el.count;
  }
  return mesh;
}

// A value named in a message: a number as written, anything else by its type.
std::string shown(const nlohmann::json& v) { return v.is_number() ? v.dump() : std::string("a ") + v.type_name(); }

// A glTF primitive's mode and its vertex count (its index accessor's, else
// its POSITION accessor's). assimp 5.2 takes a strip, fan or loop's
// primitive count as the vertex count less the vertices of its first
// primitive, unsigned: a triangle strip or fan of no vertices asked for
// 2^32 - 2 faces (64 GiB, found by fuzz_model), one of 1 vertex and a line
// strip of none for 2^32 - 1, and an indexed fan of 2 or an indexed loop
// of under 2 read or freed memory that was not theirs. Each mode is
// checked to be one glTF 2 defines and to have at least the vertices of
// one of its primitives, and the accessors a primitive names are checked
// to exist. Sparse ones among them are refused: assimp 5.2 copies a
// sparse accessor's substitutions without checking their count or indices
// against the buffers (a heap overrun). Those no primitive names (morph
// targets' usually, taken out below) are left: assimp reads only the
// accessors something names.
void check_gltf_primitives(const nlohmann::json& j, const std::string& name) {
  const auto meshes = j.find("meshes");
  if (meshes == j.end() || !meshes->is_array()) return;
  const auto accessors = j.find("accessors");
  const size_t n_accessors = accessors != j.end() && accessors->is_array() ? accessors->size() : 0;
  static const char* const kModes[] = {"points",    "lines",          "line loop",   "line strip",
                                       "triangles", "triangle strip", "triangle fan"};
  static const uint64_t kLeast[] = {0, 0, 2, 2, 0, 3, 3};  // vertices the first primitive of a strip, fan or loop needs
  for (size_t m = 0; m < meshes->size(); ++m) {
    const auto& mesh = (*meshes)[m];
    const auto prims = mesh.is_object() ? mesh.find("primitives") : mesh.end();
    if (!mesh.is_object() || prims == mesh.end() || !prims->is_array()) continue;
    for (size_t p = 0; p < prims->size(); ++p) {
      const auto& prim = (*prims)[p];
      if (!prim.is_object()) continue;
      const std::string what = "glTF mesh " + std::to_string(m) + " primitive " + std::to_string(p);
      uint64_t mode = 4;  // triangles, glTF 2's default
      if (const auto it = prim.find("mode"); it != prim.end()) {
        if (!it->is_number_unsigned() || it->get<uint64_t>() > 6)
          bad(name, what + " has mode " + shown(*it) + "; glTF 2 defines modes 0 to 6");
        mode = it->get<uint64_t>();
      }
      // The accessors named: the index accessor, whose count is the
      // vertex count when it is there, then the attributes' (POSITION's
      // count is the vertex count otherwise).
      struct Named {
        std::string role;
        const nlohmann::json* index;
        bool counts;  // its count is the vertex count
      };
      std::vector<Named> named;
      const auto indices = prim.find("indices");
      const bool indexed = indices != prim.end();
      if (indexed) named.push_back({"indices", &*indices, true});
      if (const auto attr = prim.find("attributes"); attr != prim.end() && attr->is_object())
        for (auto it = attr->begin(); it != attr->end(); ++it)
          named.push_back({it.key(), &*it, !indexed && it.key() == "POSITION"});
      uint64_t vertices = UINT64_MAX;  // neither named
      for (const auto& [role, index, counts] : named) {
        if (!index->is_number_unsigned() || index->get<uint64_t>() >= n_accessors)
          bad(name, what + "'s " + printable(role) + " names accessor " + shown(*index) + ", which does not exist");
        const std::string accessor_named = "glTF accessor " + shown(*index) + " (" + what + "'s " + printable(role) + ")";
        const auto& accessor = (*accessors)[size_t(index->get<uint64_t>())];
        const auto count = accessor.is_object() ? accessor.find("count") : accessor.end();
        if (!accessor.is_object() || count == accessor.end() || !count->is_number_unsigned())
          bad(name, accessor_named + " has no count");
        if (accessor.contains("sparse")) bad(name, accessor_named + " is sparse; oovr does not read sparse accessors");
        if (counts) vertices = count->get<uint64_t>();
      }
      // Neither named: assimp reads no positions and draws the primitive
      // from none (glTF 2, 3.7.2.1: a client skips it), so a strip, fan or
      // loop of it is a strip of no vertices (fuzz_model, in CI, found a
      // position-less line strip asking for 2^32 - 1 faces).
      if (vertices == UINT64_MAX) vertices = 0;
      if (vertices < kLeast[mode])
        bad(name, what + " is a " + kModes[mode] + " of " + std::to_string(vertices) + (vertices == 1 ? " vertex" : " vertices") +
                      "; a " + kModes[mode] + " needs at least " + std::to_string(kLeast[mode]));
    }
  }
}

// glTF 2 JSON: buffers no larger than the bytes that hold them, accessors
// with counts within the limits, a node graph of bounded depth and
// instances, primitives assimp can read. Returns the document without
// what oovr does not draw.
std::string check_gltf_json(const std::string& text, const std::string& name, uint64_t glb_bin_bytes, bool glb) {
  const InputLimits& lim = InputLimits::get();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text, nullptr, true, false);
  } catch (const std::exception& e) {
    bad(name, std::string("bad glTF JSON: ") + e.what());
  }
  if (!j.is_object()) bad(name, "the glTF JSON is not an object");
  // An image's media type: assimp 5.2 takes an embedded image's file
  // extension as what follows the '/' in it, and read from address 1 where
  // there is none (fuzz_model: "image*png"; a data URI's type is read the
  // same way). glTF 2 names its types "image/png" and "image/jpeg";
  // extensions name others the same way. A URI has no control character
  // (RFC 3986), and assimp marks a data URI it has parsed by a first byte
  // of 0x10, then reads offsets from the bytes after it.
  const auto media_type = [&](const std::string& type, const std::string& what) {
    if (type.find('/') == std::string::npos)
      bad(name, what + " is '" + printable(type) + "', not a media type such as 'image/png'");
  };
  const auto check_uri = [&](const nlohmann::json& item, const std::string& what, bool image) {
    const auto uri = item.is_object() ? item.find("uri") : item.end();
    if (!item.is_object() || uri == item.end() || !uri->is_string()) return;
    const std::string& u = uri->get_ref<const std::string&>();
    if (std::any_of(u.begin(), u.end(), [](char c) { return uint8_t(c) < 0x20 || c == 0x7f; }))
      bad(name, what + "'s uri has a control character, which no URI has");
    if (image && u.rfind("data:", 0) == 0) {
      const size_t end = std::min(u.find_first_of(";,", 5), u.size());
      if (end > 5) media_type(u.substr(5, end - 5), what + "'s data URI's media type");
    }
  };
  if (const auto it = j.find("buffers"); it != j.end() && it->is_array()) {
    for (size_t i = 0; i < it->size(); ++i) {
      const auto& b = (*it)[i];
      if (!b.is_object()) bad(name, "glTF buffer " + std::to_string(i) + " is not an object");
      check_uri(b, "glTF buffer " + std::to_string(i), false);
      const auto len = b.find("byteLength");
      if (len == b.end() || !len->is_number_unsigned()) bad(name, "glTF buffer " + std::to_string(i) + " has no byteLength");
      const uint64_t bytes = len->get<uint64_t>();
      check_limit(bytes, lim.file_bytes, "file_bytes", "model '" + name + "' buffer " + std::to_string(i), "bytes");
      const auto uri = b.find("uri");
      if (uri == b.end()) {
        if (!glb || i != 0) bad(name, "glTF buffer " + std::to_string(i) + " has no uri");
        if (bytes > glb_bin_bytes)
          bad(name, "glTF buffer 0 declares " + std::to_string(bytes) + " bytes, the GLB's binary chunk has " +
                        std::to_string(glb_bin_bytes));
      } else if (uri->is_string()) {
        const std::string u = uri->get<std::string>();
        if (u.rfind("data:", 0) == 0) {
          const size_t comma = u.find(',');
          const uint64_t decoded = comma == std::string::npos ? 0 : (u.size() - comma - 1) / 4 * 3;
          if (bytes > decoded)
            bad(name, "glTF buffer " + std::to_string(i) + " declares " + std::to_string(bytes) + " bytes, its data URI holds " +
                          std::to_string(decoded));
        } else {
          const fs::path file = fs::path(name).parent_path() / u;
          std::error_code ec;
          const uint64_t size = fs::is_regular_file(file, ec) ? fs::file_size(file, ec) : 0;
          if (!ec && bytes > size)
            bad(name, "glTF buffer " + std::to_string(i) + " declares " + std::to_string(bytes) + " bytes, '" + u + "' has " +
                          std::to_string(size));
        }
      }
    }
  }
  // The node tree's depth (assimp walks it recursively): an explicit walk
  // from every node, refusing cycles (a node among its own descendants)
  // and trees deeper than the limit.
  if (const auto it = j.find("nodes"); it != j.end() && it->is_array()) {
    const size_t n = it->size();
    check_limit(n, lim.elements, "elements", "model '" + name + "'", "glTF nodes");
    std::vector<std::vector<size_t>> children(n);
    for (size_t i = 0; i < n; ++i) {
      const auto& node = (*it)[i];
      const auto c = node.is_object() ? node.find("children") : node.end();
      if (!node.is_object() || c == node.end() || !c->is_array()) continue;
      for (const auto& k : *c) {
        if (!k.is_number_unsigned() || k.get<uint64_t>() >= n)
          bad(name, "glTF node " + std::to_string(i) + " names a child that does not exist");
        children[i].push_back(size_t(k.get<uint64_t>()));
      }
    }
    // Depth and instances of each node's subtree, children first
    // (iterative, so a deep file cannot overflow this check's stack
    // either). Instances saturate just above the limit.
    const uint64_t cap = lim.draws + 1;
    std::vector<int> depth(n, -1), state(n, 0);  // state: 0 unseen, 1 on the path, 2 done
    std::vector<uint64_t> instances(n, 0);
    for (size_t root = 0; root < n; ++root) {
      if (state[root]) continue;
      std::vector<std::pair<size_t, size_t>> stack{{root, 0}};
      state[root] = 1;
      while (!stack.empty()) {
        auto& [node, next] = stack.back();
        if (next < children[node].size()) {
          const size_t c = children[node][next++];
          if (state[c] == 1) bad(name, "glTF node " + std::to_string(c) + " is its own descendant");
          if (state[c] == 0) {
            state[c] = 1;
            stack.push_back({c, 0});
          }
          continue;
        }
        int d = 1;
        uint64_t count = 1;
        for (const size_t c : children[node]) {
          d = std::max(d, depth[c] + 1);
          count = std::min(cap, count + instances[c]);
        }
        depth[node] = d;
        instances[node] = count;
        state[node] = 2;
        check_limit(uint64_t(d), uint64_t(lim.nesting), "nesting", "model '" + name + "'", "levels of glTF nodes");
        stack.pop_back();
      }
    }
    // The instances assimp makes: every subtree under a scene's root, and
    // under each node without a parent (counted too, to be safe).
    std::vector<bool> has_parent(n, false), root(n, false);
    for (const auto& c : children)
      for (const size_t k : c) has_parent[k] = true;
    for (size_t i = 0; i < n; ++i) root[i] = !has_parent[i];
    if (const auto sc = j.find("scenes"); sc != j.end() && sc->is_array())
      for (const auto& scene : *sc) {
        const auto nodes = scene.is_object() ? scene.find("nodes") : scene.end();
        if (!scene.is_object() || nodes == scene.end() || !nodes->is_array()) continue;
        for (const auto& k : *nodes)
          if (k.is_number_unsigned() && k.get<uint64_t>() < n) root[size_t(k.get<uint64_t>())] = true;
      }
    uint64_t total = 0;
    for (size_t i = 0; i < n; ++i)
      if (root[i]) total = std::min(cap, total + instances[i]);
    if (total > lim.draws)
      exceeded_limit(lim.draws, "draws", "model '" + name + "'",
                     "glTF node instances (a node under several parents counts once under each)");
  }
  if (const auto it = j.find("accessors"); it != j.end() && it->is_array()) {
    for (const auto& a : *it) {
      const auto c = a.is_object() ? a.find("count") : a.end();
      if (a.is_object() && c != a.end() && c->is_number_unsigned())
        check_limit(c->get<uint64_t>(), lim.elements, "elements", "model '" + name + "'", "elements in an accessor");
    }
  }
  check_gltf_primitives(j, name);
  if (const auto it = j.find("images"); it != j.end() && it->is_array())
    for (size_t i = 0; i < it->size(); ++i) {
      const auto& image = (*it)[i];
      const std::string what = "glTF image " + std::to_string(i);
      check_uri(image, what, true);
      const auto type = image.is_object() ? image.find("mimeType") : image.end();
      if (!image.is_object() || type == image.end()) continue;
      if (!type->is_string())
        bad(name, what + "'s mimeType is a " + std::string(type->type_name()) + ", not a media type such as 'image/png'");
      media_type(type->get<std::string>(), what + "'s mimeType");
    }
  // glTF 1 (2015) keeps its collections in objects keyed by id, which none
  // of the checks above reads, and assimp 5.2's glTF 1 reader aborts the
  // program (an ai_assert) on a buffer without its byteLength (fuzz_model):
  // a reader oovr cannot make safe, so only glTF 2 is read.
  const nlohmann::json* version = nullptr;
  if (const auto asset = j.find("asset"); asset != j.end() && asset->is_object())
    if (const auto v = asset->find("version"); v != asset->end()) version = &*v;
  if (!version || !version->is_string() || version->get<std::string>().rfind("2.", 0) != 0)
    bad(name, "the glTF asset's version is " +
                  (!version               ? std::string("missing")
                   : version->is_string() ? "'" + printable(version->get<std::string>()) + "'"
                                          : shown(*version)) +
                  "; oovr reads glTF 2 only (assimp's glTF 1 reader aborts on malformed files)");
  // Skins, animations and morph targets move or blend geometry over time;
  // oovr draws a model's rest pose, so they are taken out here rather than
  // left to assimp (whose glTF 2 importer crashes on some skins).
  j.erase("skins");
  j.erase("animations");
  const auto drop = [](nlohmann::json& array, std::initializer_list<const char*> keys) {
    if (!array.is_array()) return;
    for (auto& item : array)
      if (item.is_object())
        for (const char* k : keys) item.erase(k);
  };
  if (const auto it = j.find("nodes"); it != j.end()) drop(*it, {"skin", "weights"});
  if (const auto it = j.find("meshes"); it != j.end() && it->is_array()) {
    drop(*it, {"weights"});
    for (auto& mesh : *it)
      if (mesh.is_object())
        if (const auto p = mesh.find("primitives"); p != mesh.end()) {
          drop(*p, {"targets"});
          // Points and lines (modes 0 to 3; checked above) have no
          // triangles for oovr to draw, and assimp 5.2 closes an indexed
          // line loop through its first line even where it dropped that
          // line for an index past the vertices (a null read, found by
          // trying each mode with indices out of range): they are taken out.
          if (p->is_array()) {
            nlohmann::json kept = nlohmann::json::array();
            for (auto& prim : *p) {
              const auto mode = prim.is_object() ? prim.find("mode") : prim.end();
              if (mode == prim.end() || mode->get<uint64_t>() >= 4) kept.push_back(std::move(prim));
            }
            *p = std::move(kept);
          }
        }
  }
  return j.dump();
}

uint32_t le32(const std::string& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;  // glTF is little-endian, as every machine oovr builds on
}

void put_le32(std::string& out, uint32_t v) {
  char c[4];
  std::memcpy(c, &v, 4);
  out.append(c, 4);
}

// GLB: a 12-byte header (magic, version, length) and chunks of (length,
// type, data); the lengths must match the bytes that are there. Returns
// the GLB rebuilt around the checked JSON, with the first binary chunk.
std::string check_glb(const std::string& b, const std::string& name) {
  if (b.size() < 12 || b.compare(0, 4, "glTF") != 0) bad(name, "not a GLB file (no 'glTF' magic)");
  if (le32(b, 4) != 2) bad(name, "GLB version " + std::to_string(le32(b, 4)) + "; oovr reads glTF 2 (GLB version 2) only");
  if (le32(b, 8) != b.size())
    bad(name, "the GLB header declares " + std::to_string(le32(b, 8)) + " bytes, the file has " + std::to_string(b.size()));
  size_t at = 12;
  std::string json;
  std::string_view bin;
  bool has_bin = false;
  while (at < b.size()) {
    if (b.size() - at < 8) bad(name, "a truncated GLB chunk header");
    const uint64_t len = le32(b, at), type = le32(b, at + 4);
    if (len > b.size() - at - 8)
      bad(name, "a GLB chunk declares " + std::to_string(len) + " bytes, " + std::to_string(b.size() - at - 8) + " remain");
    if (type == 0x4E4F534Au && json.empty()) json = b.substr(at + 8, size_t(len));  // "JSON"
    else if (type == 0x004E4942u && !has_bin) {                                     // "BIN\0"
      bin = std::string_view(b).substr(at + 8, size_t(len));
      has_bin = true;
    }
    at += 8 + size_t(len);
  }
  if (json.empty()) bad(name, "the GLB file has no JSON chunk");
  std::string checked = check_gltf_json(json, name, bin.size(), true);
  checked.append((4 - checked.size() % 4) % 4, ' ');  // chunks are 4-byte aligned, JSON padded with spaces
  std::string out = b.substr(0, 8);
  put_le32(out, 0);  // the total, set below
  put_le32(out, uint32_t(checked.size()));
  put_le32(out, 0x4E4F534Au);
  out += checked;
  if (has_bin) {
    put_le32(out, uint32_t(bin.size()));
    put_le32(out, 0x004E4942u);
    out += bin;
  }
  if (out.size() > UINT32_MAX) bad(name, "the GLB file is too large");
  const uint32_t total = uint32_t(out.size());
  std::memcpy(out.data() + 8, &total, 4);
  return out;
}

// OBJ (Wavefront): assimp makes a mesh for every group, object and
// material change, and keeps every vertex, texture coordinate, normal and
// face index; these are counted here against the limits before it reads
// the file. Its material libraries are read through oovr's IO system
// (regular files within file_bytes only).
void check_obj(const std::string& bytes, const std::string& name) {
  const InputLimits& lim = InputLimits::get();
  // OBJ is text. assimp 5.2's reader ends some of its scans at a NUL and
  // not others, and a face list of lines with NULs in them wrote past its
  // buffers (fuzz_model: ASan's allocator found its own chunk headers
  // overwritten).
  if (const size_t nul = bytes.find('\0'); nul != std::string::npos)
    bad(name, "an OBJ file is text, and byte " + std::to_string(nul) + " is a NUL");
  uint64_t groups = 0, elements = 0;
  size_t at = 0;
  while (at < bytes.size()) {
    size_t end = bytes.find('\n', at);
    if (end == std::string::npos) end = bytes.size();
    std::string_view line = std::string_view(bytes).substr(at, end - at);
    at = end + 1;
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    const size_t space = line.find_first_of(" \t");
    const std::string_view word = line.substr(0, space);
    if (word == "g" || word == "o" || word == "usemtl") {
      if (++groups > lim.draws)
        exceeded_limit(lim.draws, "draws", "model '" + name + "'", "OBJ groups, objects and material changes");
    } else if (word == "v" || word == "vt" || word == "vn" || word == "vp") {
      if (++elements > lim.elements) exceeded_limit(lim.elements, "elements", "model '" + name + "'", "OBJ elements");
    } else if (word == "f" || word == "l" || word == "p") {
      // Every index of a face is an element; a polygon is triangulated
      // into as many triangles as it has corners, less two.
      std::string_view rest = space == std::string_view::npos ? std::string_view() : line.substr(space);
      while (!rest.empty()) {
        const size_t b = rest.find_first_not_of(" \t\r\\");
        if (b == std::string_view::npos) break;
        rest.remove_prefix(b);
        ++elements;
        const size_t e = rest.find_first_of(" \t\r\\");
        rest = e == std::string_view::npos ? std::string_view() : rest.substr(e);
      }
      if (elements > lim.elements) exceeded_limit(lim.elements, "elements", "model '" + name + "'", "OBJ elements");
    }
  }
}

}  // namespace

PlyMesh read_ply(const std::string& bytes, const std::string& name) { return parse_ply(bytes, name); }

std::string precheck_model_bytes(const std::string& bytes, const std::string& name) {
  const std::string ext = lower_extension(name);
  if (ext == ".glb") return check_glb(bytes, name);
  if (ext == ".gltf") return check_gltf_json(bytes, name, 0, false);
  if (ext == ".ply") (void)read_ply(bytes, name);
  else if (ext == ".obj") check_obj(bytes, name);
  else bad(name, "not a model file oovr checks (" + (ext.empty() ? std::string("no extension") : ext) + ")");
  return bytes;
}

std::string precheck_model_file(const std::string& path) {
  return precheck_model_bytes(read_input_file(path, "model", InputLimits::get().file_bytes), path);
}

}  // namespace oovr
