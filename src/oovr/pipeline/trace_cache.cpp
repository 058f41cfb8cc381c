#include "oovr/pipeline/trace_cache.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "oovr/core/error.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'O', 'O', 'V', 'R', 'T', 'R', 'C', '1'};
// Bump when the trace's meaning or layout changes.
constexpr uint32_t kFormat = 2;

struct Hasher {
  uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const uint8_t*>(p)[i]) * 1099511628211ull;
  }
  template <class T>
  void pod(const T& v) {
    bytes(&v, sizeof v);
  }
  void str(const std::string& s) {
    pod(s.size());
    bytes(s.data(), s.size());
  }
};

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
void put_vector(std::string& out, const std::vector<T>& v) {
  put(out, uint64_t(v.size()));
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

class Reader {
 public:
  explicit Reader(const std::string& s) : m_s(s) {}
  template <class T>
  bool get(T& v) {
    if (m_s.size() - m_at < sizeof v) return false;
    std::memcpy(&v, m_s.data() + m_at, sizeof v);
    m_at += sizeof v;
    return true;
  }
  template <class T>
  bool get_vector(std::vector<T>& v) {
    uint64_t n = 0;
    if (!get(n) || n > (m_s.size() - m_at) / sizeof(T)) return false;
    v.resize(n);
    std::memcpy(v.data(), m_s.data() + m_at, n * sizeof(T));
    m_at += n * sizeof(T);
    return true;
  }
  bool done() const { return m_at == m_s.size(); }

 private:
  const std::string& m_s;
  size_t m_at = 0;
};

// A hash of the running executable: any rebuild (a fixed rasteriser, a new
// trace field) invalidates every cached trace, so a cache can never replay
// the output of older code. Hashed 8 bytes at a time, once per process.
uint64_t build_fingerprint() {
  static const uint64_t value = [] {
    std::ifstream in("/proc/self/exe", std::ios::binary);
    if (!in) return uint64_t(0);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    uint64_t h = 1469598103934665603ull ^ bytes.size();
    size_t i = 0;
    for (; i + 8 <= bytes.size(); i += 8) {
      uint64_t w;
      std::memcpy(&w, bytes.data() + i, 8);
      h = (h ^ w) * 1099511628211ull;
      h ^= h >> 29;
    }
    for (; i < bytes.size(); ++i) h = (h ^ uint8_t(bytes[i])) * 1099511628211ull;
    return h;
  }();
  return value;
}

}  // namespace

uint64_t scene_fingerprint(const Scene& s) {
  Hasher h;
  h.str(s.name);
  h.pod(s.camera.frames_per_second);
  for (const auto& t : s.textures) {
    h.pod(t.wrap);
    h.pod(t.compress);
    h.pod(t.mipmapped);
    for (const auto& l : t.levels) {
      h.pod(l.width);
      h.pod(l.height);
      h.bytes(l.rgba.data(), l.rgba.size());
    }
  }
  for (const auto& m : s.materials) {
    h.pod(m.two_sided);
    h.pod(m.passes.size());
    for (const Pass& p : m.passes) {
      h.pod(p.layers.size());
      for (const TextureLayer& l : p.layers) {
        h.pod(l.kind);
        h.pod(l.texture);
        h.pod(l.coords);
        h.pod(l.combine);
        h.pod(l.scale);
        h.pod(l.mods.size());
        for (const TexMod& mod : l.mods) {
          h.pod(mod.kind);
          h.pod(mod.s);
          h.pod(mod.t);
        }
      }
      h.pod(p.shading);
      h.pod(p.colour);
      h.pod(p.src);
      h.pod(p.dst);
      h.pod(p.alpha_func);
      h.pod(p.alpha_ref);
      h.pod(p.depth_func);
      h.pod(p.depth_write);
      h.pod(p.specular_power);
      h.pod(p.specular_intensity);
    }
  }
  for (const auto& m : s.meshes) {
    h.bytes(m.vertices.data(), m.vertices.size() * sizeof(Vertex));
    h.bytes(m.indices.data(), m.indices.size() * sizeof(uint32_t));
    h.bytes(m.frames.data(), m.frames.size() * sizeof(TangentFrame));
  }
  for (const auto& o : s.objects) {
    h.pod(o.mesh);
    h.pod(o.material);
    h.pod(o.pass);
    h.pod(o.world_from_object);
  }
  return h.h;
}

TraceCache::TraceCache(std::string directory) : m_dir(std::move(directory)) {
  if (const char* m = std::getenv("OOVR_CACHE_MAX_MB"); m && *m) {
    char* end = nullptr;
    errno = 0;
    const unsigned long long mb = std::strtoull(m, &end, 10);
    if (errno != 0 || *end != '\0' || m[0] == '-')
      throw Error(std::string("OOVR_CACHE_MAX_MB must be a whole number of megabytes, not '") + m + "'");
    m_max_bytes = uint64_t(mb) << 20;
  }
  if (!m_dir.empty()) return;
  if (const char* d = std::getenv("OOVR_CACHE_DIR"); d && *d) m_dir = d;
  else if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) m_dir = std::string(x) + "/oovr/traces";
  else if (const char* home = std::getenv("HOME"); home && *home) m_dir = std::string(home) + "/.cache/oovr/traces";
  else m_dir = (fs::temp_directory_path() / "oovr-traces").string();
}

std::string TraceCache::key(uint64_t fingerprint, int frame, const StereoView& view, const PipelineSettings& s) const {
  Hasher h;
  h.pod(kFormat);
  h.pod(build_fingerprint());
  h.pod(fingerprint);
  h.pod(frame);
  h.pod(view.eyes);
  h.pod(view.frame_width);
  h.pod(view.frame_height);
  for (int e = 0; e < view.eyes; ++e) {
    h.pod(view.viewport[e]);
    h.pod(view.clip_from_world[e]);
  }
  h.pod(s.max_anisotropy);
  h.pod(s.line_bytes);
  h.pod(s.texture_format);
  h.pod(s.record_texture_lines);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h.h));
  return buf;
}

std::string serialize_trace(const FrameTrace& t) {
  std::string out(kMagic, sizeof kMagic);
  put(out, kFormat);
  put(out, t.frame);
  put(out, t.frame_width);
  put(out, t.frame_height);
  put(out, t.tile_size);
  put(out, t.tiles_x);
  put(out, t.tiles_y);
  put(out, t.line_bytes);
  put(out, t.block_w);
  put(out, t.block_h);
  put(out, t.texture_format);
  put_vector(out, t.objects);
  put_vector(out, t.tiles);
  put_vector(out, t.tex_lines);
  return out;
}

std::optional<FrameTrace> deserialize_trace(const std::string& bytes) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) return std::nullopt;
  const std::string body = bytes.substr(sizeof kMagic);
  Reader r(body);
  FrameTrace t;
  uint32_t format = 0;
  if (!r.get(format) || format != kFormat) return std::nullopt;
  if (!(r.get(t.frame) && r.get(t.frame_width) && r.get(t.frame_height) && r.get(t.tile_size) && r.get(t.tiles_x) &&
        r.get(t.tiles_y) && r.get(t.line_bytes) && r.get(t.block_w) && r.get(t.block_h) && r.get(t.texture_format) && r.get_vector(t.objects) &&
        r.get_vector(t.tiles) && r.get_vector(t.tex_lines) && r.done()))
    return std::nullopt;
  // Reject anything a reader could trip over.
  if (uint8_t(t.texture_format) > uint8_t(TextureFormat::bc)) return std::nullopt;
  for (const TileWork& w : t.tiles)
    if (w.object >= t.objects.size() || w.eye > 1 || w.tile_x >= t.tiles_x || w.tile_y >= t.tiles_y ||
        w.tex_begin + w.tex_count > t.tex_lines.size())
      return std::nullopt;
  return t;
}

std::optional<FrameTrace> TraceCache::load(const std::string& key) const {
  const fs::path path = fs::path(m_dir) / (key + ".trace");
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream buf;
  buf << in.rdbuf();
  auto t = deserialize_trace(buf.str());
  // A hit is recent use: trim() drops the least recently used first.
  std::error_code ec;
  if (t) fs::last_write_time(path, fs::file_time_type::clock::now(), ec);
  return t;
}

void TraceCache::trim(const fs::path& keep) const {
  struct Entry {
    fs::file_time_type time;
    uint64_t bytes;
    fs::path path;
  };
  std::vector<Entry> entries;
  uint64_t total = 0;
  std::error_code ec;
  for (fs::directory_iterator it(m_dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().extension() != ".trace" || it->path() == keep) continue;
    std::error_code e2;
    const uint64_t bytes = it->file_size(e2);
    const auto time = it->last_write_time(e2);
    if (e2) continue;
    entries.push_back({time, bytes, it->path()});
    total += bytes;
  }
  total += fs::file_size(keep, ec);
  if (total <= m_max_bytes) return;
  // Oldest first; ties broken by name so two processes agree.
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.time != b.time ? a.time < b.time : a.path < b.path; });
  for (const Entry& e : entries) {
    if (total <= m_max_bytes) break;
    if (fs::remove(e.path, ec)) total -= e.bytes;
  }
}

bool TraceCache::store(const std::string& key, const FrameTrace& t) const {
  std::error_code ec;
  fs::create_directories(m_dir, ec);
  if (ec) return false;
  // Write aside, then rename: readers never see a half-written file.
  const fs::path final_path = fs::path(m_dir) / (key + ".trace");
  const fs::path tmp = fs::path(m_dir) / (key + ".tmp" + std::to_string(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary);
    const std::string bytes = serialize_trace(t);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out) {
      fs::remove(tmp, ec);
      return false;
    }
  }
  fs::rename(tmp, final_path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return false;
  }
  trim(final_path);
  return true;
}

}  // namespace oovr
