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
  const size_t end = bytes.find("end_header");
  if (end == std::string::npos) bad(name, "the PLY header has no end_header");
  const size_t newline = bytes.find('\n', end);
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
    }
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
// with counts within the limits.
void check_gltf_json(const std::string& text, const std::string& name, uint64_t glb_bin_bytes, bool glb) {
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
    // Depth of each node's subtree, children first (iterative, so a deep
    // file cannot overflow this check's stack either).
    std::vector<int> depth(n, -1), state(n, 0);  // state: 0 unseen, 1 on the path, 2 done
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
        for (const size_t c : children[node]) d = std::max(d, depth[c] + 1);
        depth[node] = d;
        state[node] = 2;
        check_limit(uint64_t(d), uint64_t(lim.nesting), "nesting", "model '" + name + "'", "levels of glTF nodes");
        stack.pop_back();
      }
    }
  }
  if (const auto it = j.find("accessors"); it != j.end() && it->is_array()) {
    for (const auto& a : *it) {
      const auto c = a.is_object() ? a.find("count") : a.end();
      if (a.is_object() && c != a.end() && c->is_number_unsigned())
        check_limit(c->get<uint64_t>(), lim.elements, "elements", "model '" + name + "'", "elements in an accessor");
    }
  }
}

uint32_t le32(const std::string& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;  // glTF is little-endian, as every machine oovr builds on
}

// GLB: a 12-byte header (magic, version, length) and chunks of (length,
// type, data); the lengths must match the bytes that are there.
void check_glb(const std::string& b, const std::string& name) {
  if (b.size() < 12 || b.compare(0, 4, "glTF") != 0) bad(name, "not a GLB file (no 'glTF' magic)");
  if (le32(b, 8) != b.size())
    bad(name, "the GLB header declares " + std::to_string(le32(b, 8)) + " bytes, the file has " + std::to_string(b.size()));
  size_t at = 12;
  std::string json;
  uint64_t bin = 0;
  while (at < b.size()) {
    if (b.size() - at < 8) bad(name, "a truncated GLB chunk header");
    const uint64_t len = le32(b, at), type = le32(b, at + 4);
    if (len > b.size() - at - 8)
      bad(name, "a GLB chunk declares " + std::to_string(len) + " bytes, " + std::to_string(b.size() - at - 8) + " remain");
    if (type == 0x4E4F534Au && json.empty()) json = b.substr(at + 8, size_t(len));  // "JSON"
    else if (type == 0x004E4942u && bin == 0) bin = len;                            // "BIN\0"
    at += 8 + size_t(len);
  }
  if (json.empty()) bad(name, "the GLB file has no JSON chunk");
  check_gltf_json(json, name, bin, true);
}

}  // namespace

void precheck_model_bytes(const std::string& bytes, const std::string& name) {
  const std::string ext = lower_extension(name);
  if (ext == ".ply") check_ply(bytes, name);
  else if (ext == ".glb") check_glb(bytes, name);
  else if (ext == ".gltf") check_gltf_json(bytes, name, 0, false);
}

void precheck_model_file(const std::string& path) {
  const InputLimits& lim = InputLimits::get();
  const std::string ext = lower_extension(path);
  // Either way only a regular file within the bound gets to assimp; the
  // formats with declared sizes are read and checked.
  if (ext == ".ply" || ext == ".glb" || ext == ".gltf")
    precheck_model_bytes(read_input_file(path, "model", lim.file_bytes), path);
  else check_input_file(path, "model", lim.file_bytes);
}

}  // namespace oovr
