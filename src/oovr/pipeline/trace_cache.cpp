#include "oovr/pipeline/trace_cache.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <type_traits>
#include <vector>

#include "oovr/core/bytes.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/hash.h"
#include "oovr/core/host.h"
#include "oovr/core/text.h"
#include "oovr/pipeline/tiled_layout.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'O', 'O', 'V', 'R', 'T', 'R', 'C', '1'};
// Bump when the trace's meaning or layout changes (3: key and checksum).
constexpr uint32_t kFormat = 3;

uint64_t checksum(std::string_view b) { return checksum64(b); }

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

// Records are written as their bytes, so they must have no padding whose
// bytes nobody set (a checksum would see noise).
static_assert(std::has_unique_object_representations_v<TileWork>);
static_assert(std::has_unique_object_representations_v<ObjectWork>);
static_assert(std::has_unique_object_representations_v<TexLine>);

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
  h.pod(kFormat);
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

std::string serialize_trace(const FrameTrace& t) {
  std::string out;
  out.reserve(64 + t.objects.size() * sizeof(ObjectWork) + t.tiles.size() * sizeof(TileWork) +
              t.tex_lines.size() * sizeof(TexLine));
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

std::optional<FrameTrace> deserialize_trace(std::string_view bytes) {
  ByteReader r(bytes);
  FrameTrace t;
  if (!(r.get(t.frame) && r.get(t.frame_width) && r.get(t.frame_height) && r.get(t.tile_size) && r.get(t.tiles_x) &&
        r.get(t.tiles_y) && r.get(t.line_bytes) && r.get(t.block_w) && r.get(t.block_h) && r.get(t.texture_format)))
    return std::nullopt;
  // The header first, so that nothing below divides by or indexes with a
  // value the renderer could not have written.
  constexpr int kMaxSide = 1 << 16;
  if (t.frame < 0 || t.frame_width <= 0 || t.frame_height <= 0 || t.frame_width > kMaxSide || t.frame_height > kMaxSide ||
      t.tile_size != kTileSize || t.tiles_x != (t.frame_width + kTileSize - 1) / kTileSize ||
      t.tiles_y != (t.frame_height + kTileSize - 1) / kTileSize || t.line_bytes < 32 || t.line_bytes > 1024 ||
      (t.line_bytes & (t.line_bytes - 1)) != 0 || uint8_t(t.texture_format) > uint8_t(TextureFormat::bc))
    return std::nullopt;
  int bw = 0, bh = 0;
  line_block_shape(t.line_bytes, bw, bh);
  if (t.block_w != bw || t.block_h != bh) return std::nullopt;
  if (!(r.get_vector(t.objects) && r.get_vector(t.tiles) && r.get_vector(t.tex_lines) && r.done())) return std::nullopt;
  // Tile records in the renderer's order, (object, eye, tile_y, tile_x),
  // each once, each naming a tile of the frame and a range of its lines.
  const auto order = [](const TileWork& w) { return std::array<uint64_t, 4>{w.object, w.eye, w.tile_y, w.tile_x}; };
  for (size_t i = 0; i < t.tiles.size(); ++i) {
    const TileWork& w = t.tiles[i];
    if (w.object >= t.objects.size() || w.eye >= kEyes || w.tile_x >= t.tiles_x || w.tile_y >= t.tiles_y ||
        w.tex_begin > t.tex_lines.size() || w.tex_count > t.tex_lines.size() - w.tex_begin)
      return std::nullopt;
    if (i > 0 && !(order(t.tiles[i - 1]) < order(w))) return std::nullopt;
  }
  return t;
}

std::string encode_entry(const std::string& key, const FrameTrace& t) {
  const std::string payload = serialize_trace(t);
  std::string out(kMagic, sizeof kMagic);
  put(out, kFormat);
  put(out, uint32_t(key.size()));
  out += key;
  put(out, uint64_t(payload.size()));
  put(out, checksum(payload));
  out += payload;
  return out;
}

std::optional<FrameTrace> decode_entry(std::string_view bytes, const std::string& key, std::string* why) {
  const auto fail = [&](const std::string& w) -> std::optional<FrameTrace> {
    if (why) *why = w;
    return std::nullopt;
  };
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    return fail("not a trace-cache entry (bad magic)");
  ByteReader r(bytes.substr(sizeof kMagic));
  uint32_t format = 0, key_size = 0;
  if (!r.get(format)) return fail("truncated header");
  if (format != kFormat) return fail("format " + std::to_string(format) + ", expected " + std::to_string(kFormat));
  std::string_view stored_key;
  if (!r.get(key_size) || !r.get_bytes(key_size, stored_key)) return fail("truncated header");
  if (stored_key != key) return fail("stored under another key");
  uint64_t size = 0, sum = 0;
  if (!r.get(size) || !r.get(sum)) return fail("truncated header");
  if (size != r.left()) return fail("payload of " + std::to_string(r.left()) + " bytes, the header says " + std::to_string(size));
  const std::string_view payload = bytes.substr(bytes.size() - size);
  if (checksum(payload) != sum) return fail("checksum mismatch");
  auto t = deserialize_trace(payload);
  if (!t) return fail("inconsistent trace");
  return t;
}

std::string trace_mismatch(const FrameTrace& t, const Scene& scene, int frame, const StereoView& view,
                           const PipelineSettings& settings) {
  if (t.frame != frame) return "a trace of frame " + std::to_string(t.frame) + ", not " + std::to_string(frame);
  if (t.frame_width != view.frame_width || t.frame_height != view.frame_height)
    return "a trace of a " + std::to_string(t.frame_width) + "x" + std::to_string(t.frame_height) + " frame";
  if (t.line_bytes != settings.line_bytes || t.texture_format != settings.texture_format)
    return "a trace with another line size or texture format";
  if (t.objects.size() != scene.draws(frame).size())
    return "a trace of " + std::to_string(t.objects.size()) + " objects, the scene's frame has " +
           std::to_string(scene.draws(frame).size());
  for (const TileWork& w : t.tiles)
    if (w.eye >= view.eyes) return "a trace with more eyes than the view";
  if (!settings.record_texture_lines && !t.tex_lines.empty()) return "a trace with texture lines where none are recorded";
  // Lines per texture in its storage format (tiled_layout.h).
  std::vector<uint64_t> lines(scene.textures.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    int bw = 0, bh = 0;
    texture_line_shape(scene.textures[i], settings.texture_format, settings.line_bytes, bw, bh);
    lines[i] = texture_layout(scene.textures[i], bw, bh).lines;
  }
  for (const TexLine l : t.tex_lines) {
    const uint32_t tex = tex_line_texture(l);
    if (tex >= lines.size() || tex_line_index(l) >= lines[tex]) return "a texture line outside the scene's textures";
  }
  return {};
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
