// Loads OBJ, glTF 2, PLY and AC3D files through assimp. Each (node, mesh)
// instance becomes one object (one draw) in node order. Textures are
// de-duplicated by their resolved source (canonical path, or embedded index),
// so materials that name the same image share one texture, as a real engine
// would bind one texture object for all of them.
#include <assimp/GltfMaterial.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <stb_image.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/scene/formats/model_checks.h"
#include "oovr/scene/load.h"
#include "oovr/scene/source.h"

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

// The model files oovr reads, by extension.
bool is_model_path(const std::string& path) {
  static const char* kSupported[] = {".obj", ".gltf", ".glb", ".ply", ".ac", ".acc", ".ac3d"};
  const std::string ext = lower_extension(path);
  return std::find(std::begin(kSupported), std::end(kSupported), ext) != std::end(kSupported);
}

class AssimpLoader {
 public:
  explicit AssimpLoader(const std::string& path) : m_path(path), m_dir(fs::path(path).parent_path()) {}

  Scene load() {
    if (!is_model_path(m_path))
      throw Error("cannot load '" + m_path + "': unsupported file type (supported: .obj .gltf .glb .ply .ac .acc .ac3d)");
    if (!fs::exists(m_path)) throw NotFoundError("cannot load '" + m_path + "': no such file");
    precheck_model_file(m_path);  // what assimp would trust: declared counts and lengths
    Assimp::Importer importer;
    // Points and lines are removed; only triangles are drawn.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* s = importer.ReadFile(m_path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                                                     aiProcess_ValidateDataStructure);
    if (!s || (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !s->mRootNode)
      throw Error("cannot load '" + m_path + "': " + importer.GetErrorString());
    m_ai = s;
    m_scene.name = fs::path(m_path).stem().string();
    m_scene.description = "loaded from " + m_path;
    m_material_of.assign(s->mNumMaterials, -1);
    m_mesh_of.assign(s->mNumMeshes, -1);
    visit(s->mRootNode, Mat4::identity());
    if (m_scene.objects.empty()) throw Error("cannot load '" + m_path + "': the file has no triangles");
    make_camera_path();
    m_scene.validate();
    return std::move(m_scene);
  }

 private:
  void visit(const aiNode* node, const Mat4& parent) {
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
      m_scene.objects.push_back({name, m_mesh_of[mi], mat, world});
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) visit(node->mChildren[c], world);
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
    MipLevel l;
    if (t->mHeight == 0) {  // compressed image data of mWidth bytes
      int w = 0, h = 0, n = 0;
      stbi_uc* data = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(t->pcData), int(t->mWidth), &w, &h, &n, 4);
      if (!data) throw Error("cannot load '" + m_path + "': embedded texture '" + ref + "' cannot be decoded");
      l.width = w;
      l.height = h;
      l.rgba.resize(size_t(w) * h * 4);
      const size_t row = size_t(w) * 4;
      for (int y = 0; y < h; ++y) std::memcpy(&l.rgba[row * size_t(h - 1 - y)], data + row * size_t(y), row);
      stbi_image_free(data);
    } else {
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
    }
    return l;
  }

  void make_camera_path() {
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (const auto& o : m_scene.objects)
      for (const auto& v : m_scene.meshes[size_t(o.mesh)].vertices) {
        const Vec3 p = transform_point3(o.world_from_object, v.position);
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
    m_scene.camera = orbit_camera_path(lo, hi, 120);
  }

  std::string m_path;
  fs::path m_dir;
  const aiScene* m_ai = nullptr;
  Scene m_scene;
  std::vector<int> m_material_of, m_mesh_of;
  std::map<std::string, int> m_textures;
};

// Model files are asked after the built-in scenes: any name that is an
// existing file (a path may contain ':', so this runs when no prefix claimed
// it), or that names a model file by its extension, so that a missing one
// is "no such file", not an unknown scene.
const SceneSources::Add reg("file", {"model file", "a model file path (OBJ, glTF, PLY, AC3D)", false, 10, nullptr,
                                     [](const std::string& name) {
                                       std::error_code ec;
                                       return fs::exists(name, ec) || is_model_path(name);
                                     },
                                     [](const std::string&, const std::string& path, const SceneOptions&) {
                                       return AssimpLoader(path).load();
                                     },
                                     nullptr});

}  // namespace

}  // namespace oovr
