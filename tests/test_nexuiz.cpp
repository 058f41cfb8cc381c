// The nexuiz: source on a synthetic game directory (a pk3 holding a BSP
// without a lightmap lump, external lm_NNNN.tga lightmaps and deluxe maps,
// and a texture with _norm and _gloss companions): DarkPlaces' one lit
// pass, the deluxe maps turned into oovr's frame, and what happens when
// lightmaps are missing or corrupt. The installed maps are tested in
// test_game_levels.cpp.
#include <gtest/gtest.h>
#include <zip.h>

#include <cstdlib>
#include <map>
#include <string>

#include "game_data.h"
#include "oovr/core/error.h"
#include "oovr/scene/load.h"
#include "oovr/scene/sources/nexuiz.h"
#include "temp_dir.h"

namespace oovr {
namespace {

// An uncompressed 24-bit TGA, top row first, every pixel (r, g, b).
std::string tga(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  std::vector<char> t(18 + size_t(w) * size_t(h) * 3, '\0');
  t[2] = 2;  // true colour
  t[12] = char(w & 255);
  t[13] = char(w >> 8);
  t[14] = char(h & 255);
  t[15] = char(h >> 8);
  t[16] = 24;
  t[17] = 0x20;  // top-left origin
  for (size_t i = 18; i < t.size(); i += 3) {
    t[i] = char(b);
    t[i + 1] = char(g);
    t[i + 2] = char(r);
  }
  return std::string(t.begin(), t.end());
}

class NexuizDir : public ::testing::Test {
 protected:
  NexuizDir() {
    const auto bsp = test::make_test_bsp();
    std::vector<uint8_t> external = bsp;
    // Empty the lightmap lump (q3map2 -external): its length goes to 0.
    test::put32(external, 12 + 14 * 8, 0);
    m_files["maps/test.bsp"] = std::string(external.begin(), external.end());
    m_files["maps/test/lm_0000.tga"] = tga(8, 8, 200, 100, 50);
    m_files["maps/test/lm_0001.tga"] = tga(8, 8, 255, 128, 0);  // Quake direction (+x, 0, -z) roughly
    m_files["textures/test/wall.tga"] = tga(4, 4, 255, 255, 255);
    m_files["textures/test/wall_norm.tga"] = tga(4, 4, 128, 128, 255);
    m_files["textures/test/wall_gloss.tga"] = tga(4, 4, 64, 64, 64);
    setenv("OOVR_NEXUIZ_DIR", m_tmp.path().c_str(), 1);
  }
  ~NexuizDir() override { unsetenv("OOVR_NEXUIZ_DIR"); }

  Scene load() {
    int err = 0;
    zip_t* z = zip_open((m_tmp.path() / "data.pk3").c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    EXPECT_NE(z, nullptr);
    for (const auto& [path, bytes] : m_files)
      zip_file_add(z, path.c_str(), zip_source_buffer(z, bytes.data(), bytes.size(), 0), ZIP_FL_OVERWRITE);
    EXPECT_EQ(zip_close(z), 0);
    return load_scene("nexuiz:test");
  }

  static const Pass& wall(const Scene& s) {
    for (const Object& o : s.objects)
      if (o.name.find("wall lm0") != std::string::npos) return s.pass_of(o);
    throw Error("no lightmapped wall");
  }

  static bool noted(const Scene& s, const std::string& text) {
    for (const auto& n : s.notes)
      if (n.find(text) != std::string::npos) return true;
    return false;
  }

  test::TempDir m_tmp;
  std::map<std::string, std::string> m_files;
};

TEST_F(NexuizDir, LightmappedSurfacesAreLitPerPixelInOnePass) {
  const Scene s = load();
  const Pass& p = wall(s);
  EXPECT_EQ(p.shading, Shading::deluxe);
  ASSERT_GE(p.layer(LayerKind::normal), 0);
  ASSERT_GE(p.layer(LayerKind::gloss), 0);
  EXPECT_LT(p.layer(LayerKind::glow), 0) << "no _glow image";
  const Texture& lm = s.textures[size_t(p.layers[size_t(p.layer(LayerKind::lightmap))].texture)];
  EXPECT_EQ(lm.width(), 8);
  EXPECT_FALSE(lm.compress);
  EXPECT_EQ(lm.levels[0].rgba[0], 200) << "DarkPlaces uses the lightmap texels unchanged";
  // Quake (x, y, z) -> oovr (x, z, -y): texel (r, g, b) -> (r, b, 255 - g).
  const Texture& dm = s.textures[size_t(p.layers[size_t(p.layer(LayerKind::deluxe))].texture)];
  EXPECT_EQ(dm.levels[0].rgba[0], 255);
  EXPECT_EQ(dm.levels[0].rgba[1], 0);
  EXPECT_EQ(dm.levels[0].rgba[2], 127);
  for (const Object& o : s.objects) {
    const Mesh& m = s.meshes[size_t(o.mesh)];
    if (s.pass_of(o).shading == Shading::deluxe) {
      EXPECT_EQ(m.frames.size(), m.vertices.size());
    }
  }
  EXPECT_TRUE(noted(s, "2 lightmap images of 8x8 from maps/test/lm_NNNN.tga, in lightmap and deluxe map pairs"));
  EXPECT_TRUE(noted(s, "lit per pixel"));
}

TEST_F(NexuizDir, WithoutDeluxeMapsTheLightmapModulates) {
  m_files.erase("maps/test/lm_0001.tga");
  const Scene s = load();
  const Pass& p = wall(s);
  EXPECT_EQ(p.shading, Shading::layers);
  EXPECT_GE(p.layer(LayerKind::lightmap), 0);
  EXPECT_TRUE(noted(s, "without deluxe maps"));
}

TEST_F(NexuizDir, AMissingLightmapIsANoteAndAnUnlitSurface) {
  m_files.erase("maps/test/lm_0000.tga");
  m_files.erase("maps/test/lm_0001.tga");
  const Scene s = load();
  EXPECT_TRUE(noted(s, "name a lightmap the map does not have"));
  ASSERT_FALSE(s.objects.empty());
  for (const Object& o : s.objects) EXPECT_LT(s.pass_of(o).layer(LayerKind::lightmap), 0);
}

TEST_F(NexuizDir, CorruptOrMismatchedLightmapsAreNamedErrors) {
  m_files["maps/test/lm_0000.tga"] = "not an image";
  try {
    load();
    FAIL() << "a corrupt lightmap loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("maps/test/lm_0000.tga"), std::string::npos) << e.what();
  }
  m_files["maps/test/lm_0000.tga"] = tga(8, 4, 1, 2, 3);
  try {
    load();
    FAIL() << "a non-square lightmap loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("must be square"), std::string::npos) << e.what();
  }
  m_files["maps/test/lm_0000.tga"] = tga(16, 16, 1, 2, 3);
  EXPECT_THROW(load(), Error) << "lightmap and deluxe map of different sizes";
}

TEST_F(NexuizDir, OnePassMaterialsAreTheOldWorkload) {
  load();
  const Scene s = load_scene("nexuiz:test?materials=one-pass");
  EXPECT_EQ(s.objects.size(), s.meshes.size()) << "one pass per surface group";
  const Pass& p = wall(s);
  EXPECT_EQ(p.shading, Shading::layers);
  ASSERT_EQ(p.layers.size(), 2u);
  EXPECT_EQ(p.layers[0].kind, LayerKind::diffuse);
  EXPECT_EQ(p.layers[1].kind, LayerKind::lightmap);
  EXPECT_THROW(load_scene("nexuiz:test?materials=bogus"), Error);
}

TEST_F(NexuizDir, ListedWithItsPrefix) {
  load();
  const auto maps = list_nexuiz_maps();
  EXPECT_EQ(maps, std::vector<std::string>{"test"});
  EXPECT_TRUE(scene_data_missing("nexuiz:test").empty());
  setenv("OOVR_NEXUIZ_DIR", (m_tmp.path() / "nowhere").c_str(), 1);
  EXPECT_NE(scene_data_missing("nexuiz:test").find("not installed"), std::string::npos);
  EXPECT_TRUE(list_nexuiz_maps().empty());
}

}  // namespace
}  // namespace oovr
