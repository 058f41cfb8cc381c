#include "oovr/scene/scene_codec.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "oovr/core/bytes.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/hash.h"

namespace oovr {

namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'O', 'O', 'V', 'R', 'S', 'C', 'N', '1'};
// Bump when the scene model or this layout changes.
constexpr uint32_t kFormat = 1;
constexpr size_t kKept = 8;

// What encode_scene writes: plain values, counts before vectors and strings.
class Writer {
 public:
  std::string out;
  template <class T>
  void pod(const T& v) {
    put(out, v);
  }
  void u64(uint64_t v) { put(out, v); }
  void str(const std::string& s) { put_string(out, s); }
  template <class T>
  void pods(const std::vector<T>& v) {
    put_vector(out, v);
  }
};

// Reads what Writer wrote, with the enumerations and flags checked.
class Reader {
 public:
  explicit Reader(std::string_view s) : m_r(s) {}
  template <class T>
  bool pod(T& v) {
    return m_r.get(v);
  }
  // A count of things of at least `min_bytes` each.
  bool count(uint64_t& n, uint64_t min_bytes) { return m_r.get_count(n, min_bytes); }
  bool str(std::string& s) { return m_r.get_string(s); }
  template <class T>
  bool pods(std::vector<T>& v) {
    return m_r.get_vector(v);
  }
  // An enumeration whose values run from 0 to `last`.
  template <class E>
  bool enumeration(E& e, E last) {
    uint8_t v = 0;
    if (!m_r.get(v) || v > uint8_t(last)) return false;
    e = E(v);
    return true;
  }
  bool flag(bool& b) {
    uint8_t v = 0;
    if (!m_r.get(v) || v > 1) return false;
    b = v == 1;
    return true;
  }
  bool done() const { return m_r.done(); }

 private:
  ByteReader m_r;
};

void put_flag(Writer& w, bool b) { w.pod(uint8_t(b ? 1 : 0)); }
template <class E>
void put_enum(Writer& w, E e) {
  w.pod(uint8_t(e));
}

void put_object(Writer& w, const Object& o) {
  w.str(o.name);
  w.pod(int32_t(o.mesh));
  w.pod(int32_t(o.material));
  w.pod(o.world_from_object);
  w.pods(o.after);
  w.pod(int32_t(o.pass));
  put_enum(w, o.view);
  w.pod(o.clip_from_eye);
  w.pod(o.scissor);
}

bool get_object(Reader& r, Object& o) {
  int32_t mesh = 0, material = 0, pass = 0;
  if (!(r.str(o.name) && r.pod(mesh) && r.pod(material) && r.pod(o.world_from_object) && r.pods(o.after) && r.pod(pass) &&
        r.enumeration(o.view, DrawView::screen) && r.pod(o.clip_from_eye) && r.pod(o.scissor)))
    return false;
  o.mesh = mesh;
  o.material = material;
  o.pass = pass;
  return true;
}

bool get_objects(Reader& r, std::vector<Object>& v) {
  uint64_t n = 0;
  if (!r.count(n, 8 + 4 + 4 + sizeof(Mat4))) return false;
  v.resize(size_t(n));
  for (auto& o : v)
    if (!get_object(r, o)) return false;
  return true;
}

}  // namespace

std::string encode_scene(const Scene& s) {
  Writer w;
  w.str(s.name);
  w.str(s.description);
  w.u64(s.textures.size());
  for (const Texture& t : s.textures) {
    w.str(t.name);
    w.str(t.source);
    put_enum(w, t.wrap);
    put_flag(w, t.mipmapped);
    put_flag(w, t.opaque);
    put_flag(w, t.compress);
    w.u64(t.levels.size());
    for (const MipLevel& l : t.levels) {
      w.pod(int32_t(l.width));
      w.pod(int32_t(l.height));
      w.pods(l.rgba);
    }
  }
  w.u64(s.materials.size());
  for (const Material& m : s.materials) {
    w.str(m.name);
    put_flag(w, m.two_sided);
    put_flag(w, m.cull_front);
    w.u64(m.passes.size());
    for (const Pass& p : m.passes) {
      w.u64(p.layers.size());
      for (const TextureLayer& l : p.layers) {
        put_enum(w, l.kind);
        w.pod(int32_t(l.texture));
        put_enum(w, l.coords);
        put_enum(w, l.combine);
        w.pod(l.scale);
        w.u64(l.mods.size());
        for (const TexMod& mod : l.mods) {
          put_enum(w, mod.kind);
          w.pod(mod.s);
          w.pod(mod.t);
        }
      }
      put_enum(w, p.shading);
      w.pod(p.colour);
      put_enum(w, p.src);
      put_enum(w, p.dst);
      put_enum(w, p.alpha_func);
      w.pod(p.alpha_ref);
      put_enum(w, p.depth_func);
      put_flag(w, p.depth_write);
      put_flag(w, p.colour_write);
      w.pod(p.specular_power);
      w.pod(p.specular_intensity);
      w.pod(p.offset_factor);
      w.pod(p.offset_units);
    }
  }
  w.u64(s.meshes.size());
  for (const Mesh& m : s.meshes) {
    w.str(m.name);
    w.pods(m.vertices);
    w.pods(m.indices);
    w.pods(m.frames);
    w.pods(m.colours);
  }
  w.u64(s.objects.size());
  for (const Object& o : s.objects) put_object(w, o);
  w.u64(s.frame_objects.size());
  for (const auto& f : s.frame_objects) {
    w.u64(f.size());
    for (const Object& o : f) put_object(w, o);
  }
  w.pods(s.camera.frames);
  w.pod(s.camera.fov_y_degrees);
  w.pod(s.camera.z_near);
  w.pod(s.camera.z_far);
  w.pod(s.camera.frames_per_second);
  w.pod(s.metres_per_unit);
  w.pod(int32_t(s.capture_first_frame));
  w.pod(int32_t(s.capture_width));
  w.pod(int32_t(s.capture_height));
  w.u64(s.notes.size());
  for (const auto& n : s.notes) w.str(n);
  return std::move(w.out);
}

std::optional<Scene> decode_scene(std::string_view bytes, std::string* why) {
  const auto fail = [&](const std::string& w) -> std::optional<Scene> {
    if (why) *why = w;
    return std::nullopt;
  };
  Reader r(bytes);
  Scene s;
  uint64_t n = 0;
  if (!(r.str(s.name) && r.str(s.description) && r.count(n, 8 + 8 + 4 + 8))) return fail("truncated scene header");
  s.textures.resize(size_t(n));
  for (Texture& t : s.textures) {
    uint64_t levels = 0;
    if (!(r.str(t.name) && r.str(t.source) && r.enumeration(t.wrap, Wrap::clamp_to_edge) && r.flag(t.mipmapped) &&
          r.flag(t.opaque) && r.flag(t.compress) && r.count(levels, 16)))
      return fail("a texture is truncated or out of range");
    t.levels.resize(size_t(levels));
    for (MipLevel& l : t.levels) {
      int32_t w = 0, h = 0;
      if (!(r.pod(w) && r.pod(h) && r.pods(l.rgba))) return fail("a texture level is truncated");
      l.width = w;
      l.height = h;
    }
  }
  if (!r.count(n, 8 + 2 + 8)) return fail("truncated materials");
  s.materials.resize(size_t(n));
  for (Material& m : s.materials) {
    uint64_t passes = 0;
    if (!(r.str(m.name) && r.flag(m.two_sided) && r.flag(m.cull_front) && r.count(passes, 8)))
      return fail("a material is truncated or out of range");
    m.passes.resize(size_t(passes));
    for (Pass& p : m.passes) {
      uint64_t layers = 0;
      if (!r.count(layers, 16)) return fail("a pass is truncated");
      p.layers.resize(size_t(layers));
      for (TextureLayer& l : p.layers) {
        int32_t tex = 0;
        uint64_t mods = 0;
        if (!(r.enumeration(l.kind, LayerKind::detail) && r.pod(tex) && r.enumeration(l.coords, TexCoords::lightmap) &&
              r.enumeration(l.combine, Combine::fetch) && r.pod(l.scale) && r.count(mods, 9)))
          return fail("a texture layer is truncated or out of range");
        l.texture = tex;
        l.mods.resize(size_t(mods));
        for (TexMod& mod : l.mods)
          if (!(r.enumeration(mod.kind, TexMod::Kind::scroll) && r.pod(mod.s) && r.pod(mod.t)))
            return fail("a texture modifier is truncated or out of range");
      }
      if (!(r.enumeration(p.shading, Shading::deluxe) && r.pod(p.colour) &&
            r.enumeration(p.src, BlendFactor::one_minus_dst_alpha) && r.enumeration(p.dst, BlendFactor::one_minus_dst_alpha) &&
            r.enumeration(p.alpha_func, AlphaFunc::gequal) && r.pod(p.alpha_ref) &&
            r.enumeration(p.depth_func, DepthFunc::always) && r.flag(p.depth_write) && r.flag(p.colour_write) &&
            r.pod(p.specular_power) && r.pod(p.specular_intensity) && r.pod(p.offset_factor) && r.pod(p.offset_units)))
        return fail("a pass is truncated or out of range");
    }
  }
  if (!r.count(n, 8 * 5)) return fail("truncated meshes");
  s.meshes.resize(size_t(n));
  for (Mesh& m : s.meshes)
    if (!(r.str(m.name) && r.pods(m.vertices) && r.pods(m.indices) && r.pods(m.frames) && r.pods(m.colours)))
      return fail("a mesh is truncated");
  if (!get_objects(r, s.objects)) return fail("the draws are truncated or out of range");
  if (!r.count(n, 8)) return fail("truncated frames");
  s.frame_objects.resize(size_t(n));
  for (auto& f : s.frame_objects)
    if (!get_objects(r, f)) return fail("a frame's draws are truncated or out of range");
  int32_t first = 0, w = 0, h = 0;
  uint64_t notes = 0;
  if (!(r.pods(s.camera.frames) && r.pod(s.camera.fov_y_degrees) && r.pod(s.camera.z_near) && r.pod(s.camera.z_far) &&
        r.pod(s.camera.frames_per_second) && r.pod(s.metres_per_unit) && r.pod(first) && r.pod(w) && r.pod(h) &&
        r.count(notes, 8)))
    return fail("the camera is truncated");
  s.capture_first_frame = first;
  s.capture_width = w;
  s.capture_height = h;
  s.notes.resize(size_t(notes));
  for (auto& note : s.notes)
    if (!r.str(note)) return fail("a note is truncated");
  if (!r.done()) return fail("bytes after the scene");
  if (!(s.metres_per_unit > 0) || w < 0 || h < 0 || first < 0) return fail("a capture field out of range");
  try {
    s.validate();
  } catch (const Error& e) {
    return fail(e.what());
  }
  return s;
}

SceneCache::SceneCache(std::string directory) : m_dir(std::move(directory)) {
  if (!m_dir.empty()) return;
  if (const char* d = std::getenv("OOVR_CACHE_DIR"); d && *d) m_dir = std::string(d) + "/imports";
  else m_dir = user_cache_folder("imports");
}

std::string SceneCache::path(const std::string& key) const {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.scene", static_cast<unsigned long long>(checksum64(key)));
  return (fs::path(m_dir) / name).string();
}

std::optional<Scene> SceneCache::load(const std::string& key, std::string* why) const {
  const FileRead f = read_regular_file(path(key), uint64_t(16) << 30, false);
  if (f.failure == FileRead::Failure::missing) return std::nullopt;
  const auto fail = [&](const std::string& w) -> std::optional<Scene> {
    if (why) *why = "cached import '" + path(key) + "': " + w;
    return std::nullopt;
  };
  if (f.failure != FileRead::Failure::none) return fail(f.why);
  std::string_view b = f.bytes;
  // magic, format, key, checksum, payload
  if (b.size() < sizeof kMagic + 4 + 8 + 8 || std::memcmp(b.data(), kMagic, sizeof kMagic) != 0)
    return fail("not a cached scene");
  b.remove_prefix(sizeof kMagic);
  uint32_t format = 0;
  uint64_t key_size = 0, sum = 0;
  std::memcpy(&format, b.data(), 4);
  std::memcpy(&key_size, b.data() + 4, 8);
  b.remove_prefix(12);
  if (format != kFormat) return fail("format " + std::to_string(format) + ", not " + std::to_string(kFormat));
  if (key_size > b.size() || b.size() - key_size < 8) return fail("truncated");
  if (b.substr(0, size_t(key_size)) != key) return fail("stored under another key");
  b.remove_prefix(size_t(key_size));
  std::memcpy(&sum, b.data(), 8);
  b.remove_prefix(8);
  if (checksum64(b) != sum) return fail("checksum mismatch");
  std::string reason;
  auto s = decode_scene(b, &reason);
  if (!s) return fail(reason);
  return s;
}

void SceneCache::store(const std::string& key, const Scene& s) const {
  const std::string payload = encode_scene(s);
  std::string out(kMagic, sizeof kMagic);
  const uint32_t format = kFormat;
  const uint64_t key_size = key.size(), sum = checksum64(payload);
  out.append(reinterpret_cast<const char*>(&format), 4);
  out.append(reinterpret_cast<const char*>(&key_size), 8);
  out += key;
  out.append(reinterpret_cast<const char*>(&sum), 8);
  out += payload;
  std::error_code ec;
  fs::create_directories(m_dir, ec);
  try {
    write_output_file(path(key), out, "cached import");
  } catch (const Error&) {
    // A full disk or a read-only cache: the next run imports again.
    return;
  }
  // The newest kKept imports stay (each holds a window's textures and meshes,
  // tens of MB).
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  for (const auto& e : fs::directory_iterator(m_dir, ec))
    if (e.path().extension() == ".scene") files.emplace_back(e.last_write_time(ec), e.path());
  if (files.size() <= kKept) return;
  std::sort(files.begin(), files.end());
  for (size_t i = 0; i + kKept < files.size(); ++i) fs::remove(files[i].second, ec);
}

}  // namespace oovr
