#include "oovr/scene/openarena.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "oovr/core/error.h"
#include "oovr/scene/bsp.h"
#include "oovr/scene/load.h"
#include "oovr/scene/pk3.h"
#include "oovr/scene/q3_shader.h"

namespace oovr {
namespace {

// Quake 3 is z-up; oovr is y-up: (x, y, z) -> (x, z, -y), a rotation, so
// windings are kept. Units become metres.
Vec3 to_oovr(Vec3 q) { return Vec3{q.x, q.z, -q.y} * kQuakeUnit; }

Texture missing_texture() {
  std::vector<uint8_t> px(64 * 64 * 4);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool on = ((x / 8) + (y / 8)) % 2 == 0;
      uint8_t* p = &px[size_t(y * 64 + x) * 4];
      p[0] = on ? 255 : 40;
      p[1] = 0;
      p[2] = on ? 255 : 40;
      p[3] = 255;
    }
  return make_texture("missing", "oovr:missing", 64, 64, std::move(px));
}

std::string strip_extension(const std::string& p) {
  const auto slash = p.find_last_of('/');
  const auto dot = p.find_last_of('.');
  return dot != std::string::npos && (slash == std::string::npos || dot > slash) ? p.substr(0, dot) : p;
}

class MapBuilder {
 public:
  MapBuilder(const std::string& map, const OpenArenaOptions& opt) : m_map(map), m_opt(opt), m_fs(openarena_directory()) {}

  Scene build() {
    const std::string path = "maps/" + m_map + ".bsp";
    const auto bytes = m_fs.read(path);
    if (!bytes)
      throw Error("no map '" + m_map + "' in " + openarena_directory() + " (" + std::to_string(list_openarena_maps().size()) +
                  " maps there; 'oovr scenes' lists them)");
    const BspMap bsp = parse_bsp(bytes->data(), bytes->size(), path + " in " + m_fs.archive_of(path));
    for (const std::string& script : m_fs.list("scripts/", ".shader")) {
      const auto text = m_fs.read(script);
      parse_q3_shader_script(std::string(text->begin(), text->end()), script, m_shaders);
    }
    m_scene.name = "oa:" + m_map;
    m_scene.description = "OpenArena map " + m_map;

    struct Group {
      int shader, lightmap;
      Mesh mesh;
      std::string name;
    };
    std::vector<Group> groups;
    std::map<std::pair<int, int>, size_t> group_of;
    int billboards = 0, nodraw = 0, fog = 0, stageless = 0, patches = 0;
    std::vector<BspVertex> fv;
    std::vector<uint32_t> fi;
    for (size_t i = 0; i < bsp.faces.size(); ++i) {
      const BspFace& f = bsp.faces[i];
      if (f.type == kBspBillboard) {
        ++billboards;
        continue;
      }
      const BspShaderRef& ref = bsp.shaders[size_t(f.shader)];
      const Q3Shader* sh = shader(ref.name);
      if ((ref.surface_flags & kSurfNodraw) || (sh && sh->nodraw)) {
        ++nodraw;
        continue;
      }
      if (sh && sh->fog) {
        ++fog;
        continue;
      }
      if (sh && sh->stages.empty() && !(sh->sky && !sh->sky_box.empty())) {
        ++stageless;  // a script without stages draws nothing (its editor image is for the editor)
        continue;
      }
      patches += f.type == kBspPatch;
      fv.clear();
      fi.clear();
      bsp_face_triangles(bsp, f, m_opt.tessellation, fv, fi);
      if (fi.empty()) continue;
      const int lightmap = f.lightmap >= 0 ? f.lightmap : -1;
      size_t g;
      if (m_opt.group == OpenArenaOptions::Group::face) {
        g = groups.size();
        groups.push_back({f.shader, lightmap, {}, "face-" + std::to_string(i) + " " + ref.name});
      } else {
        const auto key = std::make_pair(f.shader, lightmap);
        const auto it = group_of.find(key);
        if (it != group_of.end()) {
          g = it->second;
        } else {
          g = groups.size();
          group_of[key] = g;
          groups.push_back({f.shader, lightmap, {}, ref.name + (lightmap >= 0 ? " lm" + std::to_string(lightmap) : "")});
        }
      }
      Mesh& mesh = groups[g].mesh;
      const uint32_t base = uint32_t(mesh.vertices.size());
      for (const BspVertex& v : fv) {
        Vertex o;
        o.position = to_oovr(v.position);
        // Quake 3's own coordinates (t = 0 at the image's top row: its
        // images are stored top row first, below), so that tcMod works in
        // the space the shader wrote it for.
        o.uv = v.st;
        o.lm_uv = v.lm;
        mesh.vertices.push_back(o);
      }
      for (uint32_t k : fi) mesh.indices.push_back(base + k);
    }

    // Surfaces are drawn in the order of their shaders' sort keys (sky,
    // opaque, decals, see-through, blended...), as ioquake3's
    // R_SortDrawSurfs; within a key, in the map's order.
    std::map<std::pair<int, int>, std::pair<int, float>> material_of;
    struct Draw {
      float sort;
      size_t group;
      int material;
    };
    std::vector<Draw> order;
    for (size_t k = 0; k < groups.size(); ++k) {
      const auto key = std::make_pair(groups[k].shader, groups[k].lightmap);
      auto it = material_of.find(key);
      if (it == material_of.end()) it = material_of.emplace(key, material(bsp, groups[k].shader, groups[k].lightmap)).first;
      order.push_back({it->second.second, k, it->second.first});
    }
    std::stable_sort(order.begin(), order.end(), [](const Draw& x, const Draw& y) { return x.sort < y.sort; });
    for (const Draw& d : order) {
      Group& g = groups[d.group];
      g.mesh.name = g.name;
      m_scene.meshes.push_back(std::move(g.mesh));
      m_scene.add_draws(g.name, int(m_scene.meshes.size()) - 1, d.material, Mat4::identity());
    }
    if (m_scene.objects.empty()) throw Error("map '" + m_map + "' has no drawable surfaces");

    if (bsp.repaired_coordinates)
      m_scene.notes.push_back(std::to_string(bsp.repaired_coordinates) + " non-finite texture or lightmap coordinates set to 0");
    if (billboards) m_scene.notes.push_back(std::to_string(billboards) + " billboard (flare) surfaces skipped");
    if (nodraw) m_scene.notes.push_back(std::to_string(nodraw) + " nodraw surfaces skipped");
    if (fog) m_scene.notes.push_back(std::to_string(fog) + " fog-volume surfaces skipped");
    if (stageless) m_scene.notes.push_back(std::to_string(stageless) + " surfaces of shaders without stages skipped (the engine draws nothing)");
    if (patches)
      m_scene.notes.push_back(std::to_string(patches) + " Bezier patches tessellated at level " + std::to_string(m_opt.tessellation));
    if (!m_missing.empty()) {
      std::string names;
      for (size_t k = 0; k < m_missing.size() && k < 8; ++k) names += (k ? ", " : "") + m_missing[k];
      if (m_missing.size() > 8) names += ", ...";
      m_scene.notes.push_back(std::to_string(m_missing.size()) + " shaders have no image in the archives and show the 'missing' texture: " + names);
    }
    m_scene.notes.push_back(std::to_string(groups.size()) + " surface groups drawn in " + std::to_string(m_scene.objects.size()) +
                            " passes (" + std::to_string(m_collapsed) + " with two stages in one multitexture pass, " +
                            std::to_string(m_blended) + " sorted after the opaque ones)");
    if (!m_unsupported.empty()) {
      std::string kinds;
      for (const auto& u : m_unsupported) kinds += (kinds.empty() ? "" : ", ") + u;
      m_scene.notes.push_back("drawn without these texture-coordinate kinds: " + kinds);
    }
    for (const auto& n : m_shaders.notes) m_scene.notes.push_back("shader script " + n);
    make_camera(bsp);
    m_scene.validate();
    return std::move(m_scene);
  }

 private:
  const Q3Shader* shader(const std::string& name) const {
    const auto it = m_shaders.shaders.find(normalize_game_path(name));
    return it == m_shaders.shaders.end() ? nullptr : &it->second;
  }

  // The archive path of an image, trying the name as given, then .jpg, .tga
  // and .png in place of its extension.
  std::optional<std::string> find_image(const std::string& name) const {
    if (name.empty()) return std::nullopt;
    const std::string p = normalize_game_path(name);
    if (m_fs.exists(p) && p.find('.') != std::string::npos) return p;
    const std::string stem = strip_extension(p);
    for (const char* ext : {".jpg", ".tga", ".png"})
      if (m_fs.exists(stem + ext)) return stem + ext;
    return std::nullopt;
  }

  int texture_for_image(const std::string& vfs_path, bool clamp) {
    const std::string key = vfs_path + (clamp ? "#clamp" : "");
    if (const auto it = m_textures.find(key); it != m_textures.end()) return it->second;
    const auto bytes = m_fs.read(vfs_path);
    MipLevel base = decode_image(bytes->data(), bytes->size(), vfs_path + " in " + m_fs.archive_of(vfs_path));
    // Quake 3 uploads an image's top row first, so t = 0 is its top.
    const size_t row = size_t(base.width) * 4;
    for (int y = 0; y < base.height / 2; ++y)
      std::swap_ranges(base.rgba.begin() + long(size_t(y) * row), base.rgba.begin() + long(size_t(y + 1) * row),
                       base.rgba.begin() + long(size_t(base.height - 1 - y) * row));
    m_scene.textures.push_back(make_texture(vfs_path, "pk3:" + vfs_path, base.width, base.height, std::move(base.rgba),
                                            clamp ? Wrap::clamp_to_edge : Wrap::repeat));
    return m_textures[key] = int(m_scene.textures.size()) - 1;
  }

  int missing() {
    if (m_missing_texture < 0) {
      m_scene.textures.push_back(missing_texture());
      m_missing_texture = int(m_scene.textures.size()) - 1;
    }
    return m_missing_texture;
  }

  int lightmap_texture(const BspMap& bsp, int index) {
    if (const auto it = m_lightmaps.find(index); it != m_lightmaps.end()) return it->second;
    const size_t n = size_t(kBspLightmapSize) * kBspLightmapSize;
    std::vector<uint8_t> rgba(n * 4);
    const uint8_t* src = &bsp.lightmaps[size_t(index) * n * 3];
    // Overbright lighting as ioquake3 applies it at load time without
    // hardware gamma (R_ColorShiftLightingBytes): r_mapOverBrightBits 2
    // shifts every texel left by 2 (x4); a texel pushed past 255 is scaled
    // back so that its largest channel is 255, keeping its hue.
    for (size_t p = 0; p < n; ++p) {
      int c[3] = {src[p * 3] * 4, src[p * 3 + 1] * 4, src[p * 3 + 2] * 4};
      const int mx = std::max({c[0], c[1], c[2]});
      for (int k = 0; k < 3; ++k) {
        if (mx > 255) c[k] = c[k] * 255 / mx;
        rgba[p * 4 + size_t(k)] = uint8_t(c[k]);
      }
      rgba[p * 4 + 3] = 255;
    }
    // Lightmap rows stay in file order: lightmap coordinates address them directly.
    m_scene.textures.push_back(make_texture("lightmap " + std::to_string(index), m_scene.name + "#lm" + std::to_string(index),
                                            kBspLightmapSize, kBspLightmapSize, std::move(rgba), Wrap::clamp_to_edge,
                                            /*mipmapped=*/false));
    m_scene.textures.back().compress = false;  // engines upload lightmaps uncompressed
    return m_lightmaps[index] = int(m_scene.textures.size()) - 1;
  }

  // The images a surface's shader stages name, for q3_passes.
  struct Lookup : Q3TextureLookup {
    MapBuilder& b;
    const BspMap& bsp;
    std::string shader_name;
    int lm;
    Lookup(MapBuilder& b_, const BspMap& bsp_, std::string name, int lm_) : b(b_), bsp(bsp_), shader_name(std::move(name)), lm(lm_) {}
    int image(const Q3Stage& st) override {
      // A stage's image; for the implicit shader (no script), the shader
      // name itself.
      const auto path = b.find_image(st.image.empty() ? shader_name : st.image);
      if (path) return b.texture_for_image(*path, st.clamp);
      if (std::find(b.m_missing.begin(), b.m_missing.end(), shader_name) == b.m_missing.end()) b.m_missing.push_back(shader_name);
      return b.missing();
    }
    int lightmap() override { return lm >= 0 ? b.lightmap_texture(bsp, lm) : -1; }  // already overbright-shifted
  };

  // The material of a (shader, lightmap) group: the passes ioquake3 draws
  // it with, and their sort key.
  std::pair<int, float> material(const BspMap& bsp, int shader_index, int lightmap) {
    const BspShaderRef& ref = bsp.shaders[size_t(shader_index)];
    const Q3Shader* sh = shader(ref.name);
    Q3Shader sky;
    if (sh && sh->sky && !sh->sky_box.empty() && find_image(sh->sky_box + "_ft")) {
      // The far box first (its front face's image: oovr draws the sky
      // surfaces with their own coordinates), then the cloud layers. A box
      // whose images are not in the archives is left out.
      sky = *sh;
      Q3Stage box;
      box.image = sh->sky_box + "_ft";
      box.clamp = true;
      sky.stages.insert(sky.stages.begin(), box);
      sh = &sky;
    }
    Lookup lookup(*this, bsp, normalize_game_path(ref.name), lightmap);
    const Q3Passes q = q3_passes(sh, lookup);
    Material m;
    m.name = ref.name + (lightmap >= 0 ? " lm" + std::to_string(lightmap) : "");
    m.passes = q.passes;
    m.two_sided = sh && sh->two_sided;
    if (sh)
      for (const Q3Stage& st : sh->stages)
        for (const std::string& u : st.unsupported) m_unsupported.insert(u);
    m_collapsed += q.collapsed;
    m_blended += q.sort > q3_sort::opaque;
    m_scene.materials.push_back(std::move(m));
    return {int(m_scene.materials.size()) - 1, q.sort};
  }

  void make_camera(const BspMap& bsp) {
    struct Spawn {
      Vec3 origin;
      float yaw;
    };
    std::vector<Spawn> spawns;
    for (const BspEntity& e : bsp.entities) {
      const auto cls = e.find("classname");
      if (cls == e.end()) continue;
      const std::string c = normalize_game_path(cls->second);
      if (c != "info_player_deathmatch" && c != "info_player_start" && c.rfind("team_ctf_", 0) != 0) continue;
      if (c.rfind("team_ctf_", 0) == 0 && c.find("spawn") == std::string::npos && c.find("player") == std::string::npos) continue;
      const auto o = e.find("origin");
      if (o == e.end()) continue;
      Spawn s{};
      std::istringstream in(o->second);
      if (!(in >> s.origin.x >> s.origin.y >> s.origin.z)) continue;
      if (const auto a = e.find("angle"); a != e.end()) s.yaw = std::strtof(a->second.c_str(), nullptr);
      if (const auto a = e.find("angles"); a != e.end()) {
        std::istringstream ang(a->second);
        float pitch = 0, yaw = 0;
        if (ang >> pitch >> yaw) s.yaw = yaw;
      }
      if (std::isfinite(s.origin.x) && std::isfinite(s.origin.y) && std::isfinite(s.origin.z) && std::isfinite(s.yaw))
        spawns.push_back(s);
    }
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (const auto& mesh : m_scene.meshes)
      for (const auto& v : mesh.vertices) {
        lo = {std::min(lo.x, v.position.x), std::min(lo.y, v.position.y), std::min(lo.z, v.position.z)};
        hi = {std::max(hi.x, v.position.x), std::max(hi.y, v.position.y), std::max(hi.z, v.position.z)};
      }
    if (spawns.empty()) {
      m_scene.camera = orbit_camera_path(lo, hi, 120);
      m_scene.notes.push_back("no spawn points: the camera circles the map");
      return;
    }
    // 120 frames visiting the spawn points in entity order; at each, the
    // player's eye (26 units above the spawn origin) sweeps from 60 degrees
    // left to 60 degrees right of the spawn direction.
    CameraPath& cam = m_scene.camera;
    cam.fov_y_degrees = 90.0f;
    cam.z_near = 4.0f * kQuakeUnit;  // Quake 3's r_znear
    cam.z_far = std::max(length(hi - lo) * 1.1f, 10.0f);
    const int frames = 120;
    const int n = int(spawns.size());
    for (int k = 0; k < frames; ++k) {
      const int s = int(int64_t(k) * n / frames);
      const int first = int((int64_t(s) * frames + n - 1) / n), last = int((int64_t(s + 1) * frames + n - 1) / n) - 1;
      const float t = last > first ? float(k - first) / float(last - first) : 0.5f;
      const float yaw = radians(spawns[size_t(s)].yaw + (t - 0.5f) * 120.0f);
      const Vec3 eye_q = spawns[size_t(s)].origin + Vec3{0, 0, 26};
      CameraPose pose;
      pose.position = to_oovr(eye_q);
      pose.target = to_oovr(eye_q + Vec3{std::cos(yaw), std::sin(yaw), 0} * 100.0f);
      cam.frames.push_back(pose);
    }
    m_scene.notes.push_back("camera: " + std::to_string(n) + " spawn points, 120 frames");
  }

  std::string m_map;
  OpenArenaOptions m_opt;
  Pk3FileSystem m_fs;
  Q3ShaderSet m_shaders;
  Scene m_scene;
  std::map<std::string, int> m_textures;
  std::map<int, int> m_lightmaps;
  int m_missing_texture = -1;
  std::vector<std::string> m_missing;
  int m_blended = 0, m_collapsed = 0;
  std::set<std::string> m_unsupported;
};

}  // namespace

std::string openarena_directory() {
  if (const char* d = std::getenv("OOVR_OPENARENA_DIR"); d && *d) return d;
  return "/usr/share/games/openarena/baseoa";
}

std::vector<std::string> list_openarena_maps() {
  std::error_code ec;
  if (!std::filesystem::is_directory(openarena_directory(), ec)) return {};
  Pk3FileSystem fs(openarena_directory());
  std::vector<std::string> maps;
  for (const std::string& p : fs.list("maps/", ".bsp")) {
    const std::string name = p.substr(5, p.size() - 5 - 4);
    if (name.find('/') == std::string::npos) maps.push_back(name);
  }
  return maps;
}

Scene load_openarena_map(const std::string& map, const OpenArenaOptions& options) {
  if (options.tessellation < 1 || options.tessellation > kMaxTessellation)
    throw Error("tessellation level " + std::to_string(options.tessellation) + " is outside 1 to " +
                std::to_string(kMaxTessellation));
  if (map.empty() || map.find('/') != std::string::npos || map.find("..") != std::string::npos)
    throw Error("bad map name '" + map + "'");
  return MapBuilder(map, options).build();
}

}  // namespace oovr
