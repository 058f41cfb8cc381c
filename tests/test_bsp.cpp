// The Quake 3 BSP parser: a synthetic map, patch tessellation, and clear
// errors (never a crash) for truncated or corrupt files.
#include <gtest/gtest.h>

#include "game_data.h"
#include "oovr/core/error.h"
#include "oovr/scene/formats/bsp.h"

namespace oovr {
namespace {

TEST(Bsp, ParsesTheSyntheticMap) {
  const auto file = test::make_test_bsp();
  const BspMap m = parse_bsp(file.data(), file.size(), "test.bsp");
  ASSERT_EQ(m.shaders.size(), 1u);
  EXPECT_EQ(m.shaders[0].name, "textures/test/wall");
  EXPECT_EQ(m.faces.size(), 3u);
  EXPECT_EQ(m.lightmap_count, 1);
  ASSERT_EQ(m.entities.size(), 2u);
  EXPECT_EQ(m.entities[1].at("classname"), "info_player_deathmatch");
  EXPECT_EQ(m.entities[1].at("origin"), "16 32 24");
}

TEST(Bsp, PolygonTrianglesFaceTheirNormal) {
  const auto file = test::make_test_bsp();
  const BspMap m = parse_bsp(file.data(), file.size(), "test.bsp");
  std::vector<BspVertex> v;
  std::vector<uint32_t> idx;
  bsp_face_triangles(m, m.faces[0], 4, v, idx);
  ASSERT_EQ(idx.size(), 6u);
  // The quad lies in the y = 0 plane facing -y (its stored normal); the
  // Quake order (clockwise from the front) is reversed to counter-clockwise.
  for (size_t t = 0; t < idx.size(); t += 3) {
    const Vec3 n = cross(v[idx[t + 1]].position - v[idx[t]].position, v[idx[t + 2]].position - v[idx[t]].position);
    EXPECT_LT(n.y, 0);
  }
}

TEST(Bsp, PatchesAreTessellatedAtTheRequestedLevel) {
  const auto file = test::make_test_bsp();
  const BspMap m = parse_bsp(file.data(), file.size(), "test.bsp");
  for (int level : {1, 2, 4, 8}) {
    std::vector<BspVertex> v;
    std::vector<uint32_t> idx;
    bsp_face_triangles(m, m.faces[1], level, v, idx);
    ASSERT_EQ(v.size(), size_t((level + 1) * (level + 1)));
    EXPECT_EQ(idx.size(), size_t(level * level * 6));
    // Corners are interpolated exactly; the middle row bulges toward the
    // control point at y = 80 (a quadratic Bezier reaches half of it).
    EXPECT_FLOAT_EQ(v.front().position.x, 0);
    EXPECT_FLOAT_EQ(v.back().position.x, 64);
    if (level % 2 == 0) {
      EXPECT_FLOAT_EQ(v[size_t(level / 2)].position.y, 72);
    }
    // Every triangle faces the control points' normals (+y).
    for (size_t t = 0; t < idx.size(); t += 3) {
      const Vec3 n = cross(v[idx[t + 1]].position - v[idx[t]].position, v[idx[t + 2]].position - v[idx[t]].position);
      EXPECT_GE(n.y, 0);
    }
  }
  std::vector<BspVertex> v;
  std::vector<uint32_t> idx;
  bsp_face_triangles(m, m.faces[2], 4, v, idx);  // billboard
  EXPECT_TRUE(idx.empty());
}

TEST(Bsp, EveryTruncationIsRefused) {
  const auto file = test::make_test_bsp();
  for (size_t n = 0; n < file.size(); n += (n < 200 ? 1 : 97))
    EXPECT_THROW(parse_bsp(file.data(), n, "t.bsp"), Error) << n << " bytes";
}

TEST(Bsp, CorruptFieldsAreNamed) {
  const auto good = test::make_test_bsp();
  auto expect_error = [&](std::vector<uint8_t> bad, const std::string& words) {
    try {
      parse_bsp(bad.data(), bad.size(), "maps/x.bsp");
      ADD_FAILURE() << "accepted: " << words;
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("maps/x.bsp"), std::string::npos) << msg;
      EXPECT_NE(msg.find(words), std::string::npos) << msg;
    }
  };
  auto bad = good;
  bad[0] = 'V';
  expect_error(bad, "bad magic");
  bad = good;
  test::put32(bad, 4, 47);
  expect_error(bad, "version 47");
  bad = good;
  test::put32(bad, 8 + 13 * 8, 1 << 30);  // face lump offset
  expect_error(bad, "lies outside");
  bad = good;
  test::put32(bad, test::test_bsp_face_field(good, 0, 0), 5);  // shader index
  expect_error(bad, "names shader 5");
  bad = good;
  test::put32(bad, test::test_bsp_face_field(good, 0, 8), 9);  // type
  expect_error(bad, "unknown type 9");
  bad = good;
  test::put32(bad, test::test_bsp_face_field(good, 0, 16), 1 << 28);  // vertex count
  expect_error(bad, "vertices outside");
  bad = good;
  test::put32(bad, test::test_bsp_face_field(good, 0, 24), 5);  // meshvert count
  expect_error(bad, "multiple of 3");
  bad = good;
  // A lightmap past the lump parses (external lightmaps); the loader checks it.
  test::put32(bad, test::test_bsp_face_field(good, 0, 28), 3);
  EXPECT_EQ(parse_bsp(bad.data(), bad.size(), "test.bsp").faces[0].lightmap, 3);
  bad = good;
  test::put32(bad, test::test_bsp_face_field(good, 1, 96), 4);  // patch width
  expect_error(bad, "bad control grid");
  bad = good;
  test::put32(bad, test::test_bsp_face_field(good, 1, 100), 1 << 30);  // patch height
  expect_error(bad, "bad control grid");
}

TEST(Bsp, MalformedEntitiesAreRefused) {
  EXPECT_THROW(parse_bsp_entities("{ \"a\" \"b\"", "x"), Error);
  EXPECT_THROW(parse_bsp_entities("{ \"a\" }", "x"), Error);
  EXPECT_THROW(parse_bsp_entities("junk", "x"), Error);
  EXPECT_EQ(parse_bsp_entities(" { \"a\" \"b\" } { } ", "x").size(), 2u);
}

}  // namespace
}  // namespace oovr
