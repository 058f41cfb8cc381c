// Loads OBJ, glTF 2 and GLB files through assimp and PLY and AC3D files
// through oovr's own readers (model.h). Textures are de-duplicated by their resolved
// source (canonical path, or embedded index), so materials that name the
// same image share one texture, as a real engine would bind one texture
// object for all of them.
#include "oovr/scene/formats/model.h"

#include <assimp/GltfMaterial.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/limits.h"
#include "oovr/core/text.h"
#include "oovr/scene/formats/ac3d.h"
#include "oovr/scene/formats/model_checks.h"
#include "oovr/scene/load.h"
#include "oovr/scene/texture.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

Mat4 to_mat4(const aiMatrix4x4& a) {
  // aiMatrix4x4 is row-major (a.a1..a.a4 is the first row).
  Mat4 m;
  const float r[4][4] = {{a.a1, a.a2, a.a3, a.a4}, {a.b1, a.b2, a.b3, a.b4}, {a.c1, a.c2, a.c3, a.c4}, {a.d1, a.d2, a.d3, a.d4}};
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) m.at(row, col) = r[row][col];
  return m;
}

const char* const kSupported[] = {".obj", ".gltf", ".glb", ".ply", ".ac", ".acc", ".ac3d"};

bool is_ac3d_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".ac" || ext == ".acc" || ext == ".ac3d";
}

// A file assimp reads, from memory.
class StringStream : public Assimp::IOStream {
 public:
  explicit StringStream(std::string bytes) : m_bytes(std::move(bytes)) {}
  size_t Read(void* out, size_t size, size_t count) override {
    if (size == 0) return 0;
    const size_t n = std::min(count, (m_bytes.size() - m_at) / size);
    std::memcpy(out, m_bytes.data() + m_at, n * size);
    m_at += n * size;
    return n;
  }
  size_t Write(const void*, size_t, size_t) override { return 0; }
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    const size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? m_at : m_bytes.size();
    if (offset > m_bytes.size() - base) return aiReturn_FAILURE;
    m_at = base + offset;
    return aiReturn_SUCCESS;
  }
  size_t Tell() const override { return m_at; }
  size_t FileSize() const override { return m_bytes.size(); }
  void Flush() override {}

 private:
  std::string m_bytes;
  size_t m_at = 0;
};

// What assimp may open: the checked model file, from memory, and (when
// `others`) regular files within file_bytes, read whole and bounded. A
// file that exists but is refused is remembered, for the error.
class BoundedIOSystem : public Assimp::IOSystem {
 public:
  BoundedIOSystem(std::string main_path, std::string main_bytes, bool others)
      : m_main(std::move(main_path)),
        m_bytes(std::move(main_bytes)),
        m_others(others),
        m_text_others(lower_extension(m_main) == ".obj") {}

  bool Exists(const char* file) const override {
    if (is_main(file)) return true;
    std::error_code ec;
    return m_others && fs::exists(file, ec);  // opened (and refused, when not a plain file) in Open
  }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (std::strpbrk(mode, "wa+")) return nullptr;
    if (is_main(file)) return new StringStream(m_bytes);
    if (!m_others) return nullptr;
    FileRead r = read_regular_file(file, InputLimits::get().file_bytes);
    if (r.failure == FileRead::Failure::too_large)
      m_refused = std::string("'") + file + "', larger than the limit of " + std::to_string(InputLimits::get().file_bytes) +
                  " bytes ($OOVR_LIMITS file_bytes)";
    else if (r.failure != FileRead::Failure::none && r.failure != FileRead::Failure::missing)
      m_refused = std::string("'") + file + "', which cannot be read: " + r.why;
    if (r.failure == FileRead::Failure::none && m_text_others && r.bytes.find('\0') != std::string::npos) {
      // An OBJ's material libraries are text, and assimp's reader of
      // them scans to NULs as its OBJ reader does (check_obj).
      m_refused = std::string("'") + file + "', a material library with a NUL byte in it (it is text)";
      return nullptr;
    }
    if (r.failure != FileRead::Failure::none) return nullptr;
    return new StringStream(std::move(r.bytes));
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }

  // The first file refused ("" when none).
  const std::string& refused() const { return m_refused; }

 private:
  bool is_main(const char* file) const {
    if (m_main == file) return true;
    std::error_code ec;
    return m_others && fs::equivalent(m_main, file, ec);
  }
  std::string m_main, m_bytes;
  bool m_others;
  bool m_text_others;  // the other files are an OBJ's material libraries
  std::string m_refused;
};

class AssimpLoader {
 public:
  AssimpLoader(const std::string& path, bool others) : m_path(path), m_dir(fs::path(path).parent_path()), m_others(others) {}

  Scene load(const std::string& checked_bytes) {
    Assimp::Importer importer;
    auto* io = new BoundedIOSystem(m_path, checked_bytes, m_others);
    importer.SetIOHandler(io);  // the importer owns it
    // Points and lines are removed; only triangles are drawn.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* s = importer.ReadFile(m_path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                                                     aiProcess_ValidateDataStructure);
    if (!io->refused().empty()) throw Error("cannot load '" + m_path + "': it names " + io->refused());
    if (!s || (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !s->mRootNode) {
      // assimp gives no reason for a scene it marks incomplete because no
      // mesh is left (points and lines taken out, here or by the checks).
      std::string why = importer.GetErrorString();
      if (why.empty())
        why = s && s->mNumMeshes == 0 ? "the file has no triangles" : "assimp could not read it and gave no reason";
      throw Error("cannot load '" + m_path + "': " + why);
    }
    m_ai = s;
    m_scene.name = fs::path(m_path).stem().string();
    m_scene.description = "loaded from " + m_path;
    m_material_of.assign(s->mNumMaterials, -1);
    m_mesh_of.assign(s->mNumMeshes, -1);
    visit(s->mRootNode, Mat4::identity(), 0);
    if (m_scene.objects.empty()) throw Error("cannot load '" + m_path + "': the file has no triangles");
    m_scene.camera = orbit_camera_around(m_scene);
    m_scene.validate();
    return std::move(m_scene);
  }

 private:
  void visit(const aiNode* node, const Mat4& parent, int depth) {
    // The checks bound glTF's node depth; other formats' trees are bounded
    // here, before this recursion could run out of stack.
    check_limit(uint64_t(depth) + 1, uint64_t(InputLimits::get().nesting), "nesting", "model '" + m_path + "'",
                "levels of nodes");
    if (m_scene.objects.size() > InputLimits::get().draws)
      exceeded_limit(InputLimits::get().draws, "draws", "model '" + m_path + "'", "draws");
    const Mat4 world = parent * to_mat4(node->mTransformation);
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      const unsigned mi = node->mMeshes[i];
      const aiMesh* am = m_ai->mMeshes[mi];
      if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || am->mNumFaces == 0) continue;
      if (m_mesh_of[mi] < 0) m_mesh_of[mi] = convert_mesh(am);
      if (m_mesh_of[mi] < 0) continue;
      const int mat = material(am->mMaterialIndex);
      std::string name = node->mName.length ? node->mName.C_Str() : "node";
      if (am->mName.length) name.append("/").append(am->mName.C_Str());
      m_scene.objects.push_back(Object::of(name, m_mesh_of[mi], mat, world));
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) visit(node->mChildren[c], world, depth + 1);
  }

  int convert_mesh(const aiMesh* am) {
    Mesh m;
    m.name = am->mName.C_Str();
    m.vertices.resize(am->mNumVertices);
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      Vertex& out = m.vertices[v];
      const aiVector3D& p = am->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw Error("cannot load '" + m_path + "': mesh '" + m.name + "' has a vertex that is not a finite number");
      out.position = {p.x, p.y, p.z};
      if (am->mTextureCoords[0]) out.uv = {am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y};
      if (am->mTextureCoords[1]) out.lm_uv = {am->mTextureCoords[1][v].x, am->mTextureCoords[1][v].y};
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;
      m.indices.insert(m.indices.end(), {face.mIndices[0], face.mIndices[1], face.mIndices[2]});
    }
    if (m.indices.empty()) return -1;
    m_scene.meshes.push_back(std::move(m));
    return int(m_scene.meshes.size()) - 1;
  }

  int material(unsigned index) {
    if (index >= m_material_of.size()) throw Error("cannot load '" + m_path + "': a mesh names a missing material");
    if (m_material_of[index] >= 0) return m_material_of[index];
    const aiMaterial* am = m_ai->mMaterials[index];
    Material m = Material::textured("", -1);
    Pass& pass = m.pass();
    aiString name;
    if (am->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
    aiColor4D colour;
    if (am->Get(AI_MATKEY_BASE_COLOR, colour) == AI_SUCCESS || am->Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS)
      pass.colour = {std::clamp(colour.r, 0.0f, 1.0f), std::clamp(colour.g, 0.0f, 1.0f), std::clamp(colour.b, 0.0f, 1.0f),
                     std::clamp(colour.a, 0.0f, 1.0f)};
    int two_sided = 0;
    if (am->Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS) m.two_sided = two_sided != 0;
    aiString alpha_mode;
    if (am->Get(AI_MATKEY_GLTF_ALPHAMODE, alpha_mode) == AI_SUCCESS && std::strcmp(alpha_mode.C_Str(), "MASK") == 0) {
      pass.alpha_func = AlphaFunc::gequal;
      float cutoff = 0.5f;
      am->Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff);
      pass.alpha_ref = cutoff;
    }
    aiString tex;
    if (am->GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == AI_SUCCESS ||
        am->GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS) {
      pass.layers.push_back({LayerKind::diffuse, texture(tex.C_Str(), m.name), TexCoords::surface, Combine::modulate, 1.0f, {}});
      // A textured material's diffuse colour in OBJ files is usually a
      // default that engines ignore when a texture is bound; keep it only
      // for glTF, where base colour factor multiplies the texture by spec.
      const std::string ext = lower_extension(m_path);
      if (ext != ".gltf" && ext != ".glb") pass.colour = {1, 1, 1, pass.colour.w};
    }
    m_scene.materials.push_back(m);
    m_material_of[index] = int(m_scene.materials.size()) - 1;
    return m_material_of[index];
  }

  int texture(const std::string& ref, const std::string& material_name) {
    std::string key;
    MipLevel base;
    std::string display = ref;
    if (const aiTexture* embedded = m_ai->GetEmbeddedTexture(ref.c_str())) {
      key = "embedded:" + m_path + "#" + ref;
      if (const auto it = m_textures.find(key); it != m_textures.end()) return it->second;
      base = decode_embedded(embedded, ref);
    } else {
      if (!m_others)
        throw Error("cannot load '" + m_path + "': material '" + material_name + "' names texture '" + ref +
                    "', and no other file is read");
      std::string rel = ref;
      std::replace(rel.begin(), rel.end(), '\\', '/');
      fs::path p = fs::path(rel).is_absolute() ? fs::path(rel) : m_dir / rel;
      std::error_code ec;
      if (!fs::is_regular_file(p, ec))
        throw Error("cannot load '" + m_path + "': material '" + material_name + "' names texture '" + ref +
                    "', which does not exist (looked for " + p.string() + ")");
      key = fs::weakly_canonical(p, ec).string();
      if (const auto it = m_textures.find(key); it != m_textures.end()) return it->second;
      base = load_image_file(p.string());
      display = p.filename().string();
    }
    m_scene.textures.push_back(make_texture(display, key, base.width, base.height, std::move(base.rgba)));
    const int id = int(m_scene.textures.size()) - 1;
    m_textures[key] = id;
    return id;
  }

  MipLevel decode_embedded(const aiTexture* t, const std::string& ref) {
    const std::string name = m_path + " embedded texture '" + ref + "'";
    if (t->mHeight == 0)  // compressed image data of mWidth bytes, decoded with its size checked first
      return decode_image(reinterpret_cast<const uint8_t*>(t->pcData), t->mWidth, name);
    const InputLimits& lim = InputLimits::get();
    check_limit(std::max(t->mWidth, t->mHeight), uint64_t(lim.image_side), "image_side", name, "texels on a side");
    check_limit(uint64_t(t->mWidth) * t->mHeight, lim.image_texels, "image_texels", name, "texels");
    MipLevel l;
    l.width = int(t->mWidth);
    l.height = int(t->mHeight);
    l.rgba.resize(size_t(l.width) * l.height * 4);
    for (int y = 0; y < l.height; ++y)
      for (int x = 0; x < l.width; ++x) {
        const aiTexel& s = t->pcData[size_t(l.height - 1 - y) * l.width + x];
        uint8_t* d = &l.rgba[(size_t(y) * l.width + x) * 4];
        d[0] = s.r;
        d[1] = s.g;
        d[2] = s.b;
        d[3] = s.a;
      }
    return l;
  }

  std::string m_path;
  fs::path m_dir;
  bool m_others;
  const aiScene* m_ai = nullptr;
  Scene m_scene;
  std::vector<int> m_material_of, m_mesh_of;
  std::map<std::string, int> m_textures;
};

}  // namespace

namespace {

// A PLY file, read by oovr's own reader (model_checks.h): one mesh, one
// untextured object.
Scene ply_scene(const std::string& bytes, const std::string& path) {
  const PlyMesh p = read_ply(bytes, path);
  if (p.indices.empty()) throw Error("cannot load '" + path + "': the file has no triangles");
  Scene scene;
  scene.name = fs::path(path).stem().string();
  scene.description = "loaded from " + path;
  Mesh m;
  m.name = scene.name;
  m.vertices.resize(p.positions.size());
  for (size_t v = 0; v < p.positions.size(); ++v) {
    m.vertices[v].position = p.positions[v];
    m.vertices[v].uv = p.uvs[v];
  }
  m.indices = p.indices;
  scene.meshes.push_back(std::move(m));
  scene.materials.push_back(Material::textured(scene.name, -1));
  scene.objects.push_back(Object::of(scene.name, 0, 0, Mat4::identity()));
  scene.camera = orbit_camera_around(scene);
  scene.validate();
  return scene;
}

}  // namespace

bool is_model_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return std::find(std::begin(kSupported), std::end(kSupported), ext) != std::end(kSupported);
}

namespace {

std::string supported_list() {
  std::string list;
  for (const char* ext : kSupported) {
    if (!list.empty()) list += ' ';
    list += ext;
  }
  return list;
}

}  // namespace

Scene load_model_file(const std::string& path) {
  if (!is_model_path(path))
    throw Error("cannot load '" + path + "': unsupported file type (supported: " + supported_list() + ")");
  std::error_code ec;
  if (!fs::exists(path, ec)) throw NotFoundError("cannot load '" + path + "': no such file");
  if (is_ac3d_path(path)) {
    // oovr's own reader, hardened and fuzzed (assimp's AC3D importer
    // recursed into 20,000 nested groups until its stack overflowed).
    Scene scene = load_ac3d_file(path, {});
    scene.camera = orbit_camera_around(scene);
    scene.validate();
    return scene;
  }
  if (lower_extension(path) == ".ply") return ply_scene(read_input_file(path, "model", InputLimits::get().file_bytes), path);
  return AssimpLoader(path, true).load(precheck_model_file(path));
}

Scene load_model_bytes(const std::string& bytes, const std::string& name) {
  if (!is_model_path(name))
    throw Error("cannot load '" + name + "': unsupported file type (supported: " + supported_list() + ")");
  if (is_ac3d_path(name)) {
    Ac3dOptions options;
    options.texture_dirs = {"/nonexistent"};  // no other file
    Scene scene = parse_ac3d(bytes, name, options);
    scene.camera = orbit_camera_around(scene);
    scene.validate();
    return scene;
  }
  if (lower_extension(name) == ".ply") return ply_scene(bytes, name);
  return AssimpLoader(name, false).load(precheck_model_bytes(bytes, name));
}

}  // namespace oovr
