#include "oovr/pipeline/trace_cache.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/hash.h"
#include "oovr/core/host.h"
#include "oovr/core/text.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

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
  h.pod(s.metres_per_unit);
  for (const auto& m : s.materials) {
    h.pod(m.two_sided);
    h.pod(m.cull_front);
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
      h.pod(p.offset_factor);
      h.pod(p.offset_units);
      h.pod(p.colour_write);
    }
  }
  for (const auto& m : s.meshes) {
    h.bytes(m.vertices.data(), m.vertices.size() * sizeof(Vertex));
    h.bytes(m.indices.data(), m.indices.size() * sizeof(uint32_t));
    h.bytes(m.frames.data(), m.frames.size() * sizeof(TangentFrame));
    h.pod(m.colours.size());
    h.bytes(m.colours.data(), m.colours.size() * sizeof(uint32_t));
  }
  const auto draws = [&](const std::vector<Object>& list) {
    h.pod(list.size());
    for (const auto& o : list) {
      h.pod(o.mesh);
      h.pod(o.material);
      h.pod(o.pass);
      h.pod(o.world_from_object);
      h.pod(o.view);
      h.pod(o.clip_from_eye);
      h.pod(o.scissor);
    }
  };
  draws(s.objects);
  h.pod(s.frame_objects.size());
  for (const auto& f : s.frame_objects) draws(f);
  return h.h;
}

TraceCache::TraceCache(std::string directory) : m_dir(std::move(directory)) {
  if (const char* m = std::getenv("OOVR_CACHE_MAX_MB"); m && *m) {
    // Digits only: strtoull alone would take " -5" as 2^64 - 5.
    const auto mb = parse_whole_number(m, 1, uint64_t(1) << 30);
    if (!mb)
      throw Error(std::string("OOVR_CACHE_MAX_MB must be a whole number of megabytes from 1 to 1073741824, not '") + m + "'");
    m_max_bytes = *mb << 20;
  }
  if (!m_dir.empty()) return;
  if (const char* d = std::getenv("OOVR_CACHE_DIR"); d && *d) m_dir = d;
  else m_dir = user_cache_folder("traces");
}

std::string TraceCache::key(uint64_t fingerprint, int frame, const StereoView& view, const PipelineSettings& s,
                            uint32_t pipeline_version) {
  Hasher h;
  h.pod(kTraceFormat);
  h.pod(pipeline_version);
  h.pod(fingerprint);
  h.pod(frame);
  h.pod(view.eyes);
  h.pod(view.frame_width);
  h.pod(view.frame_height);
  for (int e = 0; e < view.eyes; ++e) {
    h.pod(view.viewport[e]);
    h.pod(view.clip_from_world[e]);
    h.pod(view.eye_offset_m[e]);  // how captured draws are re-projected (DrawView::captured)
  }
  h.pod(s.max_anisotropy);
  h.pod(s.line_bytes);
  h.pod(s.texture_format);
  h.pod(s.record_texture_lines);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h.h));
  return buf;
}

namespace {

// Temporary files of stores are named KEY.tmp.HOST.PID: one whose process
// is gone (on this host), or older than an hour (any host: a cache folder
// may be shared by a cluster), was left by an interrupted store.
bool abandoned_temporary(const fs::directory_entry& e, const std::string& host) {
  const std::string name = e.path().filename().string();
  const size_t at = name.find(".tmp.");
  if (at == std::string::npos) return false;
  std::error_code ec;
  const auto age = fs::file_time_type::clock::now() - e.last_write_time(ec);
  if (!ec && age > std::chrono::hours(1)) return true;
  const std::string rest = name.substr(at + 5);
  const size_t dot = rest.rfind('.');
  if (dot == std::string::npos || rest.substr(0, dot) != host) return false;
  char* end = nullptr;
  const long pid = std::strtol(rest.c_str() + dot + 1, &end, 10);
  if (*end != '\0' || pid <= 0) return false;
  return ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
}

// This host's name as a file name's part.
std::string host_tag() {
  std::string h = host_name();
  if (h.empty()) return "host";
  for (char& c : h)
    if (c == '.' || c == '/') c = '_';
  return h;
}

}  // namespace

TraceLookup TraceCache::load(const std::string& key, const Scene& scene, int frame, const StereoView& view,
                             const PipelineSettings& settings) const {
  TraceLookup out;
  const fs::path path = fs::path(m_dir) / (key + ".trace");
  // Not following links: a link to /dev/zero in the cache is refused too.
  FileRead file = read_regular_file(path.string(), m_max_bytes, false);
  if (file.failure == FileRead::Failure::too_large)
    out.rejected = "larger than the cache (" + std::to_string(file.size) + " bytes)";
  else if (file.failure != FileRead::Failure::none && file.failure != FileRead::Failure::missing) out.rejected = file.why;
  if (file.failure == FileRead::Failure::none) {
    out.trace = decode_entry(file.bytes, key, &out.rejected);
    if (out.trace) {
      out.rejected = trace_mismatch(*out.trace, scene, frame, view, settings);
      if (!out.rejected.empty()) out.trace.reset();
    }
  }
  std::error_code ec;
  if (out.trace) {
    // A hit is recent use: trim() drops the least recently used first.
    fs::last_write_time(path, fs::file_time_type::clock::now(), ec);
  } else if (!out.rejected.empty()) {
    // Removed now, so that a store that cannot write does not leave it to
    // be rejected again; a store replaces it otherwise.
    out.rejected = path.filename().string() + ": " + out.rejected;
    fs::remove(path, ec);  // false without an error: another run removed it first
    if (ec) out.rejected += " (and it could not be removed: " + ec.message() + ")";
  }
  return out;
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
  const std::string host = host_tag();
  for (fs::directory_iterator it(m_dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e2;
    if (abandoned_temporary(*it, host)) {
      fs::remove_all(it->path(), e2);  // a file, or a streamed window's folder
      continue;
    }
    if (it->path().extension() != ".trace" || it->path() == keep || !it->is_regular_file(e2)) continue;
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

std::string TraceCache::temporary_path(const std::string& stem) const {
  return (fs::path(m_dir) / (stem + ".tmp." + host_tag() + "." + std::to_string(::getpid()))).string();
}

bool TraceCache::store(const std::string& key, const FrameTrace& t) const {
  std::error_code ec;
  fs::create_directories(m_dir, ec);
  if (ec) return false;
  const std::string bytes = encode_entry(key, t);
  if (bytes.size() > m_max_bytes) return false;  // would leave no room for anything else
  // Write aside, then rename: readers never see a half-written file.
  const fs::path final_path = fs::path(m_dir) / (key + ".trace");
  const fs::path tmp = temporary_path(key);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.flush();
    if (!out) {
      out.close();
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
