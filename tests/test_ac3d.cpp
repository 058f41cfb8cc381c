// The AC3D loader with TORCS's extensions: several texture lines, vertex
// normals, several uv pairs per reference, triangle strips, nested
// transforms, texture search and sharing, and clear errors.
#include <gtest/gtest.h>

#include <filesystem>

#include "oovr/core/error.h"
#include "oovr/pipeline/image.h"
#include "oovr/scene/formats/ac3d.h"
#include "oovr/scene/scene_info.h"
#include "temp_dir.h"

namespace oovr {
namespace {
namespace fs = std::filesystem;

const char* kTrack = R"(AC3Db
MATERIAL "grey" rgb 0.4 0.4 0.4  amb 0.8 0.8 0.8  emis 0 0 0  spec 0.5 0.5 0.5  shi 50  trans 0
MATERIAL "red" rgb 1 0 0  amb 0.2 0.2 0.2  emis 0 0 0  spec 0.5 0.5 0.5  shi 10  trans 0.5
OBJECT world
kids 3
OBJECT group
name "group"
loc 10 0 0
kids 2
OBJECT poly
name "road"
texture "road.png" base
texture "shadow.rgb" tiled
texture empty_texture_no_mapping skids
numvert 4
0 0 0 0 1 0
1 0 0 0 1 0
0 0 -1 0 1 0
1 0 -1 0 1 0
numsurf 1
SURF 0x14
mat 0
refs 4
0 0 0 0.5 0.5
1 1 0 0.5 0.5
2 0 1 0.5 0.5
3 1 1 0.5 0.5
kids 0
OBJECT poly
name "kerb"
texture "road.png" base
texrep 2 2
numvert 3
0 0 0
1 0 0
0 1 0
numsurf 2
SURF 0x20
mat 0
refs 3
0 0 0
1 1 0
2 0 1
SURF 0x2
mat 0
refs 2
0 0 0
1 1 0
kids 0
OBJECT poly
name "plain"
numvert 3
0 0 0
0 0 1
0 1 0
numsurf 1
SURF 0x0
mat 1
refs 3
0 0 0
1 0 0
2 0 0
kids 0
OBJECT light
name "sun"
kids 0
)";

class Ac3dDir : public ::testing::Test {
 protected:
  void SetUp() override {
    Image img(4, 4);
    for (size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;
    write_png(img, (m_dir / "road.png").string());
  }
  Scene load(const std::string& text) {
    Ac3dOptions o;
    o.texture_dirs = {m_dir.string()};
    return parse_ac3d(text, (m_dir / "track.acc").string(), o);
  }
  test::TempDir m_tmp;
  const fs::path& m_dir = m_tmp.path();
};

TEST_F(Ac3dDir, ReadsTorcsExtensions) {
  const Scene s = load(kTrack);
  ASSERT_EQ(s.objects.size(), 3u) << "three poly objects; the group and the light draw nothing";
  EXPECT_EQ(s.objects[0].name, "road");
  // A 4-vertex strip makes two triangles, both facing up (+y).
  const Mesh& road = s.meshes[size_t(s.objects[0].mesh)];
  ASSERT_EQ(road.indices.size(), 6u);
  for (size_t t = 0; t < 6; t += 3) {
    const Vec3 n = cross(road.vertices[road.indices[t + 1]].position - road.vertices[road.indices[t]].position,
                         road.vertices[road.indices[t + 2]].position - road.vertices[road.indices[t]].position);
    EXPECT_GT(n.y, 0);
  }
  EXPECT_FLOAT_EQ(road.vertices[0].position.x, 10) << "the parent group's loc applies";
  EXPECT_FLOAT_EQ(road.vertices[1].uv.x, 1) << "the first uv pair of each reference is used";
  // The kerb: line surfaces are dropped, texrep scales uv, SURF 0x20 is two-sided.
  const Mesh& kerb = s.meshes[size_t(s.objects[1].mesh)];
  EXPECT_EQ(kerb.indices.size(), 3u);
  EXPECT_FLOAT_EQ(kerb.vertices[1].uv.x, 2);
  EXPECT_TRUE(s.materials[size_t(s.objects[1].material)].two_sided);
  // Both textured objects share one texture: the base (first) texture line.
  EXPECT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(scene_info(s).max_sharing, 2);
  // The untextured object takes its material colour (trans 0.5 -> alpha 0.5).
  const Material& plain = s.materials[size_t(s.objects[2].material)];
  EXPECT_TRUE(plain.pass().layers.empty());
  EXPECT_FLOAT_EQ(plain.pass().colour.x, 1);
  EXPECT_FLOAT_EQ(plain.pass().colour.w, 0.5f);
}

TEST_F(Ac3dDir, MissingTexturesAreReportedAndShareOnePlaceholder) {
  std::string text = kTrack;
  text.replace(text.find("texture \"road.png\" base"), 23, "texture \"gone.rgb\" base");
  const Scene s = load(text);
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("gone.rgb"), std::string::npos);
  EXPECT_EQ(s.textures.size(), 2u);
}

TEST_F(Ac3dDir, ShortKidsListsAreToleratedAndNoted) {
  std::string text = kTrack;
  text.replace(text.find("kids 3"), 6, "kids 5");
  const Scene s = load(text);
  EXPECT_EQ(s.objects.size(), 3u);
  ASSERT_FALSE(s.notes.empty());
  EXPECT_NE(s.notes[0].find("declares 5 kids"), std::string::npos);
}

TEST_F(Ac3dDir, CorruptFilesNameTheLine) {
  auto expect_error = [&](const std::string& text, const std::string& words) {
    try {
      load(text);
      ADD_FAILURE() << "accepted: " << words;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("track.acc"), std::string::npos) << e.what();
    }
  };
  expect_error("OBJ\n", "no AC3D header");
  std::string t = kTrack;
  expect_error(t.substr(0, t.find("refs 4") + 8), "line");  // truncated inside a surface
  t = kTrack;
  t.replace(t.find("numvert 4"), 9, "numvert 99999999");
  expect_error(t, "exceeds what the rest of the file can hold");
  t = kTrack;
  t.replace(t.find("3 1 1 0.5 0.5"), 13, "9 1 1 0.5 0.5");
  expect_error(t, "refers to vertex 9");
  t = kTrack;
  t.replace(t.find("1 0 0 0 1 0"), 11, "1 zero 0 0 1 0");
  expect_error(t, "'zero' is not a number");
  t = kTrack;
  t.replace(t.find("SURF 0x14"), 9, "BOGUS 1");
  expect_error(t, "unexpected 'BOGUS'");
  std::string deep = "AC3Db\n";
  for (int i = 0; i < 300; ++i) deep += "OBJECT group\nkids 1\n";
  expect_error(deep, "nested more than 256 deep");
}

}  // namespace
}  // namespace oovr
