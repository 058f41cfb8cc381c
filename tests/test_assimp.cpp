// The assimp loader: OBJ, glTF, PLY, AC3D; texture de-duplication; clear
// errors for bad files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "oovr/core/error.h"
#include "oovr/pipeline/image.h"
#include "oovr/scene/load.h"
#include "oovr/scene/scene_info.h"
#include "temp_dir.h"

namespace oovr {
namespace {
namespace fs = std::filesystem;

using test::TempDir;

void write_test_png(const std::string& path, uint8_t r) {
  Image img(8, 8);
  for (size_t i = 0; i < img.rgba.size(); i += 4) {
    img.rgba[i] = r;
    img.rgba[i + 3] = 255;
  }
  write_png(img, path);
}

const char* kMtl =
    "newmtl first\nmap_Kd shared.png\n"
    "newmtl second\nmap_Kd ./shared.png\n"
    "newmtl third\nmap_Kd other.png\n";

const char* kObj =
    "mtllib scene.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "o a\nusemtl first\nf 1/1 2/2 3/3 4/4\n"
    "o b\nusemtl second\nf 5/1 6/2 7/3\n"
    "o c\nusemtl third\nf 1/1 5/2 7/3\n";

TEST(Assimp, SharedTexturesStayShared) {
  TempDir dir;
  write_test_png(dir.file("shared.png"), 200);
  write_test_png(dir.file("other.png"), 50);
  dir.file("scene.mtl", kMtl);
  const Scene s = load_scene(dir.file("scene.obj", kObj));
  EXPECT_EQ(s.objects.size(), 3u);
  ASSERT_EQ(s.textures.size(), 2u) << "two materials naming shared.png must share one texture";
  const SceneInfo i = scene_info(s);
  EXPECT_EQ(i.max_sharing, 2);
  EXPECT_EQ(s.triangle_count(), 4u);           // the quad is triangulated
  EXPECT_EQ(s.textures[0].levels.size(), 4u);  // 8x8 with its mip chain
  EXPECT_FALSE(s.camera.frames.empty());
}

TEST(Assimp, MissingTextureIsNamed) {
  TempDir dir;
  write_test_png(dir.file("shared.png"), 200);
  dir.file("scene.mtl", kMtl);  // other.png is missing
  try {
    load_scene(dir.file("scene.obj", kObj));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("other.png"), std::string::npos) << e.what();
  }
}

TEST(Assimp, BadFilesAreRefusedCleanly) {
  TempDir dir;
  EXPECT_THROW(load_scene(dir.file("model.stl", "solid x\nendsolid x\n")), Error);  // unsupported type
  EXPECT_THROW(load_scene(dir.file("truncated.ply",
                                   "ply\nformat binary_little_endian 1.0\nelement vertex 100000\n"
                                   "property float x\nproperty float y\nproperty float z\n"
                                   "element face 5\nproperty list uchar int vertex_indices\nend_header\nxx")),
               Error);
  EXPECT_THROW(load_scene(dir.file("garbage.glb", "glTF\x02\x00\x00\x00garbage")), Error);
  EXPECT_THROW(load_scene(dir.file("empty.obj", "# nothing\n")), Error);
  EXPECT_THROW(load_scene(dir.file("does-not-exist.obj")), Error);
}

// Models from Debian's assimp-testmodels package (installed by
// scripts/install-deps.sh).
const fs::path kModels = "/usr/share/assimp/models";

TEST(Assimp, DebianTestModels) {
  if (!fs::exists(kModels)) GTEST_SKIP() << "assimp-testmodels is not installed (" << kModels << ")";
  const struct {
    const char* path;
    size_t min_objects, textures;
  } cases[] = {
      {"OBJ/spider.obj", 10, 4},
      {"glTF2/BoxTextured-glTF/BoxTextured.gltf", 1, 1},
      {"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", 1, 1},
      {"PLY/Wuson.ply", 1, 0},
      {"AC/Wuson.ac", 1, 0},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.path);
    const Scene s = load_scene((kModels / c.path).string());
    EXPECT_GE(s.objects.size(), c.min_objects);
    EXPECT_EQ(s.textures.size(), c.textures);
    EXPECT_GT(s.triangle_count(), 0u);
  }
}

}  // namespace
}  // namespace oovr

namespace oovr {
namespace {

TEST(Assimp, InvalidDebianModelsAreRefused) {
  if (!fs::exists(kModels)) GTEST_SKIP() << "assimp-testmodels is not installed (" << kModels << ")";
  for (const char* path :
       {"invalid/empty.obj", "invalid/empty.ply", "invalid/malformed.obj", "glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf",
        "glTF2/MissingBin/BoxTextured.gltf", "glTF2/SchemaFailures/sceneWrongType.gltf",
        "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"}) {
    SCOPED_TRACE(path);
    // The file is there, so the error is the parser's or oovr's checks', not
    // "no such file".
    ASSERT_TRUE(fs::exists(kModels / path));
    EXPECT_THROW(load_scene((kModels / path).string()), Error);
  }
  // Partly bad files that assimp repairs load into a valid scene.
  const Scene s = load_scene((kModels / "glTF2/IndexOutOfRange/IndexOutOfRange.gltf").string());
  EXPECT_NO_THROW(s.validate());
}

}  // namespace
}  // namespace oovr
