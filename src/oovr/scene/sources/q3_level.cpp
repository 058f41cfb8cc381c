#include "oovr/scene/sources/q3_level.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "oovr/core/error.h"
#include "oovr/core/limits.h"
#include "oovr/scene/formats/bsp.h"
#include "oovr/scene/formats/pk3.h"
#include "oovr/scene/formats/q3_shader.h"
#include "oovr/scene/load.h"

namespace oovr {
namespace {

// Quake 3 is z-up; oovr is y-up: (x, y, z) -> (x, z, -y), a rotation, so
// windings are kept. Units become metres.
Vec3 to_oovr(Vec3 q) { return Vec3{q.x, q.z, -q.y} * kQuakeUnit; }
Vec3 to_oovr_direction(Vec3 q) { return Vec3{q.x, q.z, -q.y}; }

// Tangent frames of a mesh (Shading::deluxe), from its normals and surface
// texture coordinates as DarkPlaces builds them for its shaders
// (Mod_BuildTextureVectorsFromNormals): each triangle's s and t directions
// summed at its vertices, then made perpendicular to the vertex normal and
// normalised.
std::vector<TangentFrame> tangent_frames(const Mesh& mesh, const std::vector<Vec3>& normals) {
  std::vector<Vec3> sdir(mesh.vertices.size()), tdir(mesh.vertices.size());
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    const Vertex &va = mesh.vertices[a], &vb = mesh.vertices[b], &vc = mesh.vertices[c];
    const Vec3 e1 = vb.position - va.position, e2 = vc.position - va.position;
    const float s1 = vb.uv.x - va.uv.x, t1 = vb.uv.y - va.uv.y, s2 = vc.uv.x - va.uv.x, t2 = vc.uv.y - va.uv.y;
    const float det = s1 * t2 - s2 * t1;
    if (!(std::abs(det) > 1e-12f)) continue;
    const float r = 1.0f / det;
    const Vec3 sd = normalize((e1 * t2 - e2 * t1) * r), td = normalize((e2 * s1 - e1 * s2) * r);
    for (uint32_t k : {a, b, c}) {
      sdir[k] = sdir[k] + sd;
      tdir[k] = tdir[k] + td;
    }
  }
  std::vector<TangentFrame> frames(mesh.vertices.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    Vec3 n = normalize(normals[i]);
    if (!(length(n) > 0.5f)) n = {0, 1, 0};
    // Any direction perpendicular to n, for texels whose triangles had no
    // usable texture coordinates.
    const Vec3 any = std::abs(n.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    auto perpendicular = [&](Vec3 v, Vec3 fallback) {
      const Vec3 p = v - n * dot(n, v);
      return length(p) > 1e-6f ? normalize(p) : fallback;
    };
    const Vec3 s = perpendicular(sdir[i], normalize(cross(any, n)));
    const Vec3 t = perpendicular(tdir[i], normalize(cross(n, s)));
    frames[i] = {s, t, n};
  }
  return frames;
}

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
  MapBuilder(const Q3Game& game, const std::string& map, const Q3LevelOptions& opt)
      : m_game(game), m_map(map), m_opt(opt), m_fs(game.directory) {}

  Scene build() {
    const std::string path = "maps/" + m_map + ".bsp";
    const auto bytes = m_fs.read(path);
    if (!bytes)
      throw NotFoundError("no map '" + m_map + "' in " + m_game.directory + " (" + std::to_string(list_q3_maps(m_game).size()) +
                          " maps there; 'oovr scenes' lists them)");
    const BspMap bsp = parse_bsp(bytes->data(), bytes->size(), path + " in " + m_fs.archive_of(path));
    for (const std::string& script : m_fs.list("scripts/", ".shader")) {
      const auto text = m_fs.read(script);
      parse_q3_shader_script(std::string(text->begin(), text->end()), script, m_shaders);
    }
    m_scene.name = m_game.prefix + ":" + m_map;
    m_scene.description = m_game.title + " map " + m_map;
    find_lightmaps(bsp);

    struct Group {
      int shader, lightmap;
      Mesh mesh;
      std::string name;
      std::vector<Vec3> normals;  // per vertex, for tangent frames
    };
    std::vector<Group> groups;
    std::map<std::pair<int, int>, size_t> group_of;
    int billboards = 0, nodraw = 0, fog = 0, stageless = 0, patches = 0;
    uint64_t made = 0;  // vertices the faces drawn make
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
      // What tessellation will make, checked before it is made: 200 patch
      // faces sharing one large control grid once ran out of memory.
      const uint64_t level = uint64_t(std::clamp(m_opt.tessellation, 1, kMaxTessellation));
      made += f.type == kBspPatch ? uint64_t(std::max(0, (f.patch_w - 1) / 2)) * uint64_t(std::max(0, (f.patch_h - 1) / 2)) *
                                        (level + 1) * (level + 1)
                                  : uint64_t(std::max(0, f.vertex_count));
      check_limit(made, InputLimits::get().elements, "elements", "map '" + path + "'", "vertices after tessellation");
      fv.clear();
      fi.clear();
      bsp_face_triangles(bsp, f, m_opt.tessellation, fv, fi);
      if (fi.empty()) continue;
      const int lightmap = surface_lightmap(int(i), f.lightmap);
      size_t g;
      if (m_opt.group == Q3LevelOptions::Group::face) {
        g = groups.size();
        groups.push_back({f.shader, lightmap, {}, "face-" + std::to_string(i) + " " + ref.name, {}});
      } else {
        const auto key = std::make_pair(f.shader, lightmap);
        const auto it = group_of.find(key);
        if (it != group_of.end()) {
          g = it->second;
        } else {
          g = groups.size();
          group_of[key] = g;
          groups.push_back({f.shader, lightmap, {}, ref.name + (lightmap >= 0 ? " lm" + std::to_string(lightmap) : ""), {}});
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
        groups[g].normals.push_back(to_oovr_direction(v.normal));
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
      for (const Pass& p : m_scene.materials[size_t(d.material)].passes)
        if (p.shading == Shading::deluxe && g.mesh.frames.empty()) g.mesh.frames = tangent_frames(g.mesh, g.normals);
      m_scene.meshes.push_back(std::move(g.mesh));
      m_scene.add_draws(g.name, int(m_scene.meshes.size()) - 1, d.material, Mat4::identity());
    }
    if (m_scene.objects.empty()) throw Error("map '" + m_map + "' has no drawable surfaces");

    if (bsp.repaired_coordinates)
      m_scene.notes.push_back(std::to_string(bsp.repaired_coordinates) + " non-finite texture or lightmap coordinates set to 0");
    if (billboards) m_scene.notes.push_back(std::to_string(billboards) + " billboard (flare) surfaces skipped");
    if (nodraw) m_scene.notes.push_back(std::to_string(nodraw) + " nodraw surfaces skipped");
    if (fog) m_scene.notes.push_back(std::to_string(fog) + " fog-volume surfaces skipped");
    if (stageless)
      m_scene.notes.push_back(std::to_string(stageless) +
                              " surfaces of shaders without stages skipped (the engine draws nothing)");
    if (patches)
      m_scene.notes.push_back(std::to_string(patches) + " Bezier patches tessellated at level " +
                              std::to_string(m_opt.tessellation));
    if (!m_missing.empty()) {
      std::string names;
      for (size_t k = 0; k < m_missing.size() && k < 8; ++k) names += (k ? ", " : "") + m_missing[k];
      if (m_missing.size() > 8) names += ", ...";
      m_scene.notes.push_back(std::to_string(m_missing.size()) +
                              " shaders have no image in the archives and show the 'missing' texture: " + names);
    }
    m_scene.notes.push_back(std::to_string(groups.size()) + " surface groups drawn in " + std::to_string(m_scene.objects.size()) +
                            " passes (" + std::to_string(m_collapsed) + " with two stages in one multitexture pass, " +
                            std::to_string(m_blended) + " sorted after the opaque ones)");
    if (!m_unsupported.empty()) {
      std::string kinds;
      for (const auto& u : m_unsupported) kinds += (kinds.empty() ? "" : ", ") + u;
      m_scene.notes.push_back("drawn without these texture-coordinate kinds: " + kinds);
    }
    lightmap_notes();
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
    flip_rows(base);  // Quake 3 uploads an image's top row first, so t = 0 is its top
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

  // Where the map's lightmaps are and whether they come with deluxe maps.
  void find_lightmaps(const BspMap& bsp) {
    m_lightmap_count = bsp.lightmap_count;
    if (m_game.engine == Q3Engine::ioquake3) return;
    if (bsp.lightmap_count == 0) {
      // q3map2 -external: maps/<map>/lm_0000.tga, lm_0001.tga, ... up to the
      // first one missing, as DarkPlaces counts them.
      while (m_fs.exists(external_lightmap(m_lightmap_count))) ++m_lightmap_count;
      m_external = m_lightmap_count > 0;
    }
    // DarkPlaces' test: the worldspawn's deluxeMaps key says so (1: model
    // space, 2: tangent space), else an even number of lightmaps that every
    // surface names by an even index means lightmap, deluxe map pairs.
    std::string key;
    if (!bsp.entities.empty())
      for (const auto& [k, v] : bsp.entities.front())
        if (normalize_game_path(k) == "deluxemaps") key = v;
    if (key == "2") {
      m_deluxe_note = "tangent-space deluxe maps (deluxeMaps 2) are not drawn per pixel";
      return;
    }
    bool even = m_lightmap_count >= 2 && m_lightmap_count % 2 == 0;
    for (const BspFace& f : bsp.faces)
      if (f.type != kBspBillboard && f.lightmap >= 0 && f.lightmap % 2 != 0) even = false;
    m_deluxe = key == "1" || (key.empty() && even);
  }

  std::string external_lightmap(int index) const {
    char name[16];
    std::snprintf(name, sizeof name, "lm_%04d.tga", index);
    return "maps/" + m_map + "/" + name;
  }

  // The lightmap a surface is drawn with, or -1 (vertex lit). ioquake3
  // needs it in the lump; a DarkPlaces map's missing lightmap is a note and
  // a vertex-lit surface, as DarkPlaces draws it.
  int surface_lightmap(int face, int index) {
    if (index < 0) return -1;
    if (index < m_lightmap_count) return index;
    if (m_game.engine == Q3Engine::ioquake3)
      throw Error("map '" + m_map + "': face " + std::to_string(face) + " names lightmap " + std::to_string(index) + " of " +
                  std::to_string(m_lightmap_count));
    ++m_missing_lightmaps;
    return -1;
  }

  // Decodes lightmap or deluxe image `index` (external file or lump entry)
  // into RGBA rows as the engine uploads them (lightmap coordinates address
  // them directly).
  MipLevel lightmap_image(const BspMap& bsp, int index) {
    if (m_external) {
      const std::string path = external_lightmap(index);
      const auto bytes = m_fs.read(path);
      MipLevel img = decode_image(bytes->data(), bytes->size(), path + " in " + m_fs.archive_of(path));
      if (img.width != img.height || img.width < 1 || (img.width & (img.width - 1)) != 0 ||
          (m_lightmap_size && img.width != m_lightmap_size))
        throw Error(path + " in " + m_fs.archive_of(path) + ": external lightmap of " + std::to_string(img.width) + "x" +
                    std::to_string(img.height) + "; they must be square, a power of two, and all the same size");
      m_lightmap_size = img.width;
      flip_rows(img);  // decoded bottom row first; the engine uploads the top row first
      return img;
    }
    const size_t n = size_t(kBspLightmapSize) * kBspLightmapSize;
    MipLevel img{kBspLightmapSize, kBspLightmapSize, std::vector<uint8_t>(n * 4)};
    const uint8_t* src = &bsp.lightmaps[size_t(index) * n * 3];
    for (size_t p = 0; p < n; ++p) {
      for (int k = 0; k < 3; ++k) img.rgba[p * 4 + size_t(k)] = src[p * 3 + size_t(k)];
      img.rgba[p * 4 + 3] = 255;
    }
    m_lightmap_size = kBspLightmapSize;
    return img;
  }

  int lightmap_texture(const BspMap& bsp, int index) {
    if (const auto it = m_lightmaps.find(index); it != m_lightmaps.end()) return it->second;
    MipLevel img = lightmap_image(bsp, index);
    if (m_game.engine == Q3Engine::ioquake3) {
      // Overbright lighting as ioquake3 applies it at load time without
      // hardware gamma (R_ColorShiftLightingBytes): r_mapOverBrightBits 2
      // shifts every texel left by 2 (x4); a texel pushed past 255 is scaled
      // back so that its largest channel is 255, keeping its hue.
      // DarkPlaces copies the texels unchanged.
      for (size_t p = 0; p < img.rgba.size(); p += 4) {
        int c[3] = {img.rgba[p] * 4, img.rgba[p + 1] * 4, img.rgba[p + 2] * 4};
        const int mx = std::max({c[0], c[1], c[2]});
        for (int k = 0; k < 3; ++k) img.rgba[p + size_t(k)] = uint8_t(mx > 255 ? c[k] * 255 / mx : c[k]);
      }
    }
    const int size = img.width;
    m_scene.textures.push_back(make_texture("lightmap " + std::to_string(index), m_scene.name + "#lm" + std::to_string(index),
                                            size, size, std::move(img.rgba), Wrap::clamp_to_edge, /*mipmapped=*/false));
    m_scene.textures.back().compress = false;  // engines upload lightmaps uncompressed
    return m_lightmaps[index] = int(m_scene.textures.size()) - 1;
  }

  // The deluxe map of lightmap `index` (the next image), its directions
  // turned from Quake's z-up frame into oovr's: (x, y, z) -> (x, z, -y),
  // which on the stored texels is (r, g, b) -> (r, b, 255 - g), exactly.
  // -1 when the map has none.
  int deluxe_texture(const BspMap& bsp, int index) {
    if (!m_deluxe || index + 1 >= m_lightmap_count) return -1;
    if (const auto it = m_deluxes.find(index); it != m_deluxes.end()) return it->second;
    MipLevel img = lightmap_image(bsp, index + 1);
    for (size_t p = 0; p < img.rgba.size(); p += 4) {
      const uint8_t g = img.rgba[p + 1], b = img.rgba[p + 2];
      img.rgba[p + 1] = b;
      img.rgba[p + 2] = uint8_t(255 - g);
    }
    const int size = img.width;
    m_scene.textures.push_back(make_texture("deluxe " + std::to_string(index + 1),
                                            m_scene.name + "#dm" + std::to_string(index + 1), size, size, std::move(img.rgba),
                                            Wrap::clamp_to_edge, /*mipmapped=*/false));
    m_scene.textures.back().compress = false;
    return m_deluxes[index] = int(m_scene.textures.size()) - 1;
  }

  static void flip_rows(MipLevel& img) {
    const size_t row = size_t(img.width) * 4;
    for (int y = 0; y < img.height / 2; ++y)
      std::swap_ranges(img.rgba.begin() + long(size_t(y) * row), img.rgba.begin() + long(size_t(y + 1) * row),
                       img.rgba.begin() + long(size_t(img.height - 1 - y) * row));
  }

  // The images a surface's shader stages name, for q3_passes.
  struct Lookup : Q3TextureLookup {
    MapBuilder& b;
    const BspMap& bsp;
    std::string shader_name;
    int lm;
    Lookup(MapBuilder& b_, const BspMap& bsp_, std::string name, int lm_)
        : b(b_), bsp(bsp_), shader_name(std::move(name)), lm(lm_) {}
    int image(const Q3Stage& st) override {
      // A stage's image; for the implicit shader (no script), the shader
      // name itself.
      const auto path = b.find_image(st.image.empty() ? shader_name : st.image);
      if (path) return b.texture_for_image(*path, st.clamp);
      if (std::find(b.m_missing.begin(), b.m_missing.end(), shader_name) == b.m_missing.end()) b.m_missing.push_back(shader_name);
      return b.missing();
    }
    int lightmap() override { return lm >= 0 ? b.lightmap_texture(bsp, lm) : -1; }
  };

  // The pass DarkPlaces draws a scripted or implicit surface with
  // (Mod_LoadTextureFromQ3Shader): not one pass per stage as ioquake3, but
  // the shader's first image stage (its "primary layer"), with that stage's
  // blend and alpha functions; $lightmap stages are not drawn, they mark the
  // shader as lit, and a lit surface with a lightmap is lightmapped in the
  // same pass: per pixel (Shading::deluxe) over the image, the image's
  // _norm, _gloss and _glow companions (R_SkinFrame_LoadExternal looks them
  // up by the image's name) and the lightmap's deluxe map when the map has
  // deluxe maps, else image x lightmap. Further image stages are not drawn
  // (counted in a note). nullopt for shaders without an image stage (drawn
  // as ioquake3 would).
  std::optional<Q3Passes> darkplaces_passes(const BspMap& bsp, const Q3Shader* sh, Lookup& lookup, int lightmap) {
    Q3Stage implicit;
    const Q3Stage* primary = sh ? nullptr : &implicit;
    bool lighting = !sh;
    int extra = 0;
    if (sh)
      for (const Q3Stage& st : sh->stages) {
        if (st.source == Q3Stage::Source::lightmap) lighting = true;
        else if (st.source == Q3Stage::Source::image && !primary) primary = &st;
        else if (st.source == Q3Stage::Source::image) ++extra;
      }
    if (!primary) return std::nullopt;
    m_dp_skipped_stages += extra;
    Q3Passes out;
    Pass p;
    p.colour = primary->colour;
    p.src = primary->src;
    p.dst = primary->dst;
    p.alpha_func = primary->alpha_func;
    p.alpha_ref = primary->alpha_ref;
    p.depth_func = primary->depth_equal ? DepthFunc::equal : DepthFunc::lequal;
    p.depth_write = primary->depth_write;
    TextureLayer diffuse{LayerKind::diffuse, lookup.image(*primary), TexCoords::surface, Combine::modulate, 1.0f, primary->mods};
    if (sh && sh->sky) out.sort = q3_sort::environment;
    else if (sh && sh->sort > 0) out.sort = sh->sort;
    else if (primary->blended()) out.sort = primary->depth_write ? q3_sort::see_through : q3_sort::blend0;
    const int lm = lighting && lightmap >= 0 ? lookup.lightmap() : -1;
    const int deluxe = lm >= 0 ? deluxe_texture(bsp, lightmap) : -1;
    p.layers = {diffuse};
    const std::string stem = strip_extension(m_scene.textures[size_t(diffuse.texture)].name);
    const bool clamp = m_scene.textures[size_t(diffuse.texture)].wrap == Wrap::clamp_to_edge;
    auto companion = [&](const char* suffix, LayerKind kind) {
      const auto path = diffuse.texture == m_missing_texture ? std::nullopt : find_image(stem + suffix);
      if (!path) return false;
      TextureLayer l = diffuse;
      l.kind = kind;
      l.texture = texture_for_image(*path, clamp);
      if (kind == LayerKind::glow) l.combine = Combine::add;
      p.layers.push_back(l);
      return true;
    };
    if (deluxe >= 0) {
      p.shading = Shading::deluxe;
      m_layer_counts[0] += companion("_norm", LayerKind::normal);
      m_layer_counts[1] += companion("_gloss", LayerKind::gloss);
      m_layer_counts[2] += companion("_glow", LayerKind::glow);
      p.layers.push_back({LayerKind::lightmap, lm, TexCoords::lightmap, Combine::modulate, 1.0f, {}});
      p.layers.push_back({LayerKind::deluxe, deluxe, TexCoords::lightmap, Combine::modulate, 1.0f, {}});
      ++m_lit;
    } else {
      // Fixed-function order: image x lightmap, then the glow added.
      if (lm >= 0) p.layers.push_back({LayerKind::lightmap, lm, TexCoords::lightmap, Combine::modulate, 1.0f, {}});
      m_layer_counts[2] += companion("_glow", LayerKind::glow);
    }
    out.passes.push_back(std::move(p));
    return out;
  }

  // The material of a (shader, lightmap) group: the passes its engine draws
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
    std::optional<Q3Passes> dp;
    // DarkPlaces draws skies as ioquake3 does (box, then cloud layers).
    if (!m_opt.one_pass && m_game.engine == Q3Engine::darkplaces && !(sh && sh->sky))
      dp = darkplaces_passes(bsp, sh, lookup, lightmap);
    // Only the passes drawn load their images: a one-pass level holds no
    // texture it does not sample.
    const Q3Passes q = m_opt.one_pass ? one_pass(sh, lookup) : dp ? *dp : q3_passes(sh, lookup);
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

  // The one-pass material: the shader's first image stage (a sky's far box
  // comes first) times the lightmap, opaque, sorted as the map's order.
  Q3Passes one_pass(const Q3Shader* sh, Lookup& lookup) {
    const Q3Stage implicit;
    const Q3Stage* first = sh ? nullptr : &implicit;
    if (sh && !first)
      for (const Q3Stage& st : sh->stages)
        if (st.source == Q3Stage::Source::image) {
          first = &st;
          break;
        }
    Q3Passes q;
    q.passes.push_back(Pass::textured(first ? lookup.image(*first) : -1, lookup.lightmap()));
    q.passes.front().depth_func = DepthFunc::lequal;
    return q;
  }

  void lightmap_notes() {
    if (m_game.engine != Q3Engine::darkplaces) return;
    const std::string size = std::to_string(m_lightmap_size) + "x" + std::to_string(m_lightmap_size);
    if (m_lightmap_count > 0)
      m_scene.notes.push_back(std::to_string(m_lightmap_count) + " lightmap images" + (m_lightmap_size ? " of " + size : "") +
                              (m_external ? " from maps/" + m_map + "/lm_NNNN.tga" : " in the BSP") +
                              (m_deluxe ? ", in lightmap and deluxe map pairs" : ", without deluxe maps"));
    if (!m_deluxe_note.empty()) m_scene.notes.push_back(m_deluxe_note);
    if (m_lit)
      m_scene.notes.push_back(std::to_string(m_lit) + " surface groups lit per pixel (DarkPlaces deluxe mapping): " +
                              std::to_string(m_layer_counts[0]) + " with a normal map, " + std::to_string(m_layer_counts[1]) +
                              " with a gloss map, " + std::to_string(m_layer_counts[2]) + " with a glow map");
    if (m_dp_skipped_stages)
      m_scene.notes.push_back(std::to_string(m_dp_skipped_stages) +
                              " image stages after a shader's first are not drawn (DarkPlaces draws a shader's primary layer)");
    if (m_missing_lightmaps)
      m_scene.notes.push_back(std::to_string(m_missing_lightmaps) +
                              " surfaces name a lightmap the map does not have and are drawn without one");
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
      // Quake 3's and OpenArena's spawn points, and Nexuiz's team ones.
      if (c != "info_player_deathmatch" && c != "info_player_start" && c.rfind("team_ctf_", 0) != 0 &&
          c.rfind("info_player_team", 0) != 0)
        continue;
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

  Q3Game m_game;
  std::string m_map;
  Q3LevelOptions m_opt;
  Pk3FileSystem m_fs;
  Q3ShaderSet m_shaders;
  Scene m_scene;
  std::map<std::string, int> m_textures;
  std::map<int, int> m_lightmaps, m_deluxes;
  int m_missing_texture = -1;
  std::vector<std::string> m_missing;
  int m_blended = 0, m_collapsed = 0;
  std::set<std::string> m_unsupported;
  // Lightmaps: how many, where, their size, and whether in deluxe pairs.
  int m_lightmap_count = 0, m_lightmap_size = 0, m_missing_lightmaps = 0;
  bool m_external = false, m_deluxe = false;
  std::string m_deluxe_note;
  int m_lit = 0, m_dp_skipped_stages = 0;
  int m_layer_counts[3] = {0, 0, 0};  // lit groups with normal, gloss, glow maps
};

}  // namespace

Q3LevelOptions parse_q3_level_options(const std::string& spec, const SceneOptions& options) {
  Q3LevelOptions o;
  for (const auto& [k, v] : options) {
    if (k == "group") {
      if (v == "shader-lightmap") o.group = Q3LevelOptions::Group::shader_lightmap;
      else if (v == "face") o.group = Q3LevelOptions::Group::face;
      else throw Error("scene option group='" + v + "' in '" + spec + "': expected shader-lightmap or face");
    } else if (k == "tess") {
      o.tessellation = scene_int_option(k, v, spec);
    } else if (k == "materials") {
      if (v == "real") o.one_pass = false;
      else if (v == "one-pass") o.one_pass = true;
      else throw Error("scene option materials='" + v + "' in '" + spec + "': expected real or one-pass");
    } else {
      unknown_scene_option(k, spec, "Quake 3 maps take group, tess and materials");
    }
  }
  return o;
}

std::vector<std::string> list_q3_maps(const Q3Game& game) {
  std::error_code ec;
  if (!std::filesystem::is_directory(game.directory, ec)) return {};
  Pk3FileSystem fs(game.directory);
  std::vector<std::string> maps;
  for (const std::string& p : fs.list("maps/", ".bsp")) {
    const std::string name = p.substr(5, p.size() - 5 - 4);
    if (name.find('/') == std::string::npos) maps.push_back(name);
  }
  return maps;
}

std::vector<SceneListing> q3_listings(const Q3Game& game, const std::string& kind) {
  std::vector<SceneListing> out;
  for (const auto& map : list_q3_maps(game)) out.push_back({game.prefix + ":" + map, kind, game.title + " map"});
  return out;
}

Scene load_q3_level(const Q3Game& game, const std::string& map, const Q3LevelOptions& options) {
  if (options.tessellation < 1 || options.tessellation > kMaxTessellation)
    throw Error("tessellation level " + std::to_string(options.tessellation) + " is outside 1 to " +
                std::to_string(kMaxTessellation));
  if (map.empty() || map.find('/') != std::string::npos || map.find("..") != std::string::npos)
    throw Error("bad map name '" + map + "'");
  return MapBuilder(game, map, options).build();
}

}  // namespace oovr
