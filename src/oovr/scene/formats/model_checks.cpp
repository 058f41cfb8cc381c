#include "oovr/scene/formats/model_checks.h"

#include <algorithm>
#include <cctype>
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
// the records. assimp trusts the header's counts (and aborts on some
// truncated files), so the records are walked here first: every declared
// record, and every list item, must be in the file.
struct PlyProperty {
  bool list = false;
  int count_size = 0;  // bytes of a list's count (binary)
  int size = 0;        // bytes of a value or a list item (binary)
};
struct PlyElement {
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

void check_ply(const std::string& bytes, const std::string& name) {
  if (bytes.compare(0, 4, "ply\n") != 0 && bytes.compare(0, 5, "ply\r\n") != 0) bad(name, "not a PLY file (no 'ply' magic)");
  // The header ends at a line that is "end_header" alone (a property
  // named "operend_header" once looped assimp's reader for ever).
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
      std::string element;
      PlyElement e;
      words >> element >> e.count;
      if (!words) bad(name, "a PLY element without a count: '" + line + "'");
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
        if (!p.count_size || !p.size) bad(name, "unknown PLY list types in '" + line + "'");
      } else {
        p.size = ply_type_size(type);
        if (!p.size) bad(name, "unknown PLY property type '" + type + "'");
      }
      elements.back().properties.push_back(p);
    }  // other lines (comments, and the free text some exporters write) say nothing of the records
  }
  const bool ascii = format == "ascii", little = format == "binary_little_endian";
  if (!ascii && !little && format != "binary_big_endian") bad(name, "unknown PLY format '" + format + "'");
  const auto truncated = [&](const std::string& what) { bad(name, "the PLY file ends inside its " + what + " (truncated?)"); };
  size_t at = newline + 1;
  // ASCII: the next whitespace-separated token.
  const auto token = [&](const std::string& what) {
    while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    if (at >= bytes.size()) truncated(what);
    const size_t begin = at;
    while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    return std::string_view(bytes).substr(begin, at - begin);
  };
  for (size_t e = 0; e < elements.size(); ++e) {
    // A record without properties takes no bytes: nothing to walk (and
    // walking 10^8 of them took over 10 s, fuzzing found).
    if (elements[e].properties.empty()) continue;
    const std::string what = "element " + std::to_string(e) + "'s records";
    for (uint64_t r = 0; r < elements[e].count; ++r) {
      for (const PlyProperty& p : elements[e].properties) {
        if (ascii) {
          const std::string_view t = token(what);
          if (!p.list) continue;
          uint64_t n = 0;
          for (const char c : t) {
            if (c < '0' || c > '9' || n > (uint64_t(1) << 32)) bad(name, "a bad PLY list length '" + std::string(t) + "'");
            n = n * 10 + uint64_t(c - '0');
          }
          for (uint64_t i = 0; i < n; ++i) (void)token(what);
        } else {
          if (!p.list) {
            if (bytes.size() - at < size_t(p.size)) truncated(what);
            at += size_t(p.size);
            continue;
          }
          if (bytes.size() - at < size_t(p.count_size)) truncated(what);
          uint64_t n = 0;
          for (int i = 0; i < p.count_size; ++i) {
            const uint64_t byte = uint8_t(bytes[at + size_t(little ? p.count_size - 1 - i : i)]);
            n = (n << 8) | byte;
          }
          at += size_t(p.count_size);
          if (n > (bytes.size() - at) / size_t(p.size)) truncated(what);
          at += size_t(n) * size_t(p.size);
        }
      }
    }
  }
}

// glTF 2 JSON: buffers no larger than the bytes that hold them, accessors
// with counts within the limits, a node graph of bounded depth and
// instances. Returns the document without what oovr does not draw.
std::string check_gltf_json(const std::string& text, const std::string& name, uint64_t glb_bin_bytes, bool glb) {
  const InputLimits& lim = InputLimits::get();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text, nullptr, true, false);
  } catch (const std::exception& e) {
    bad(name, std::string("bad glTF JSON: ") + e.what());
  }
  if (!j.is_object()) bad(name, "the glTF JSON is not an object");
  if (const auto it = j.find("buffers"); it != j.end() && it->is_array()) {
    for (size_t i = 0; i < it->size(); ++i) {
      const auto& b = (*it)[i];
      if (!b.is_object()) bad(name, "glTF buffer " + std::to_string(i) + " is not an object");
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
        if (const auto p = mesh.find("primitives"); p != mesh.end()) drop(*p, {"targets"});
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

std::string precheck_model_bytes(const std::string& bytes, const std::string& name) {
  const std::string ext = lower_extension(name);
  if (ext == ".glb") return check_glb(bytes, name);
  if (ext == ".gltf") return check_gltf_json(bytes, name, 0, false);
  if (ext == ".ply") check_ply(bytes, name);
  else if (ext == ".obj") check_obj(bytes, name);
  else bad(name, "not a model file oovr checks (" + (ext.empty() ? std::string("no extension") : ext) + ")");
  return bytes;
}

std::string precheck_model_file(const std::string& path) {
  return precheck_model_bytes(read_input_file(path, "model", InputLimits::get().file_bytes), path);
}

}  // namespace oovr
