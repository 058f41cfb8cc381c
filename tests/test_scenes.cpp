// Built-in scenes: registered, valid, deterministic, and with the texture
// sharing they are built to show.
#include <gtest/gtest.h>

#include "oovr/scene/builtin.h"
#include "oovr/scene/load.h"
#include "oovr/scene/scene_info.h"
#include "test_util.h"

namespace oovr {
namespace {

TEST(Scenes, EveryBuiltinIsRegistered) {
  // Every scene a file of scene/builtin registers is in the registry (one
  // not compiled or not linked would be missing), and nothing else.
  const auto in_sources = test::registered_in_sources("src/oovr/scene/builtin", "BuiltinScenes");
  ASSERT_GE(in_sources.size(), 2u);
  EXPECT_EQ(BuiltinScenes::names(), in_sources);
  EXPECT_NE(BuiltinScenes::find(kDefaultScene), nullptr);
}

uint64_t fingerprint(const Scene& s) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const uint8_t*>(p)[i]) * 1099511628211ull;
  };
  for (const auto& m : s.meshes) {
    mix(m.vertices.data(), m.vertices.size() * sizeof(Vertex));
    mix(m.indices.data(), m.indices.size() * sizeof(uint32_t));
  }
  for (const auto& t : s.textures)
    for (const auto& l : t.levels) mix(l.rgba.data(), l.rgba.size());
  for (const auto& o : s.objects) mix(&o.world_from_object, sizeof(Mat4));
  for (const auto& f : s.camera.frames) mix(&f, sizeof(f));
  return h;
}

class EachBuiltin : public ::testing::TestWithParam<std::string> {};

TEST_P(EachBuiltin, ValidAndDeterministic) {
  const Scene a = load_scene(GetParam());
  const Scene b = load_scene(GetParam());
  EXPECT_NO_THROW(a.validate());
  EXPECT_EQ(fingerprint(a), fingerprint(b));
  EXPECT_GE(a.camera.frames.size(), 60u);
  for (const auto& t : a.textures) {
    if (!t.mipmapped) continue;
    EXPECT_EQ(t.levels.back().width, 1) << t.name;
    EXPECT_EQ(t.levels.back().height, 1) << t.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Builtin, EachBuiltin, ::testing::Values("courtyard", "crowd"));

TEST(Scenes, CourtyardPillarsShareOneStoneTexture) {
  const Scene s = load_scene("courtyard");
  const SceneInfo i = scene_info(s);
  int stone = -1;
  for (size_t t = 0; t < s.textures.size(); ++t)
    if (s.textures[t].name == "stone") stone = int(t);
  ASSERT_GE(stone, 0);
  EXPECT_EQ(i.texture_use[size_t(stone)].objects, 16);
  // Objects of very different weight: the statue alone has more triangles
  // than all sixteen pillars together.
  uint64_t statue = 0, pillars = 0;
  for (const auto& o : s.objects) {
    if (o.name == "statue") statue = s.meshes[size_t(o.mesh)].triangle_count();
    if (o.name.rfind("pillar-", 0) == 0) pillars += s.meshes[size_t(o.mesh)].triangle_count();
  }
  EXPECT_GT(statue, pillars);
  EXPECT_GT(i.sharing_histogram.at(1), 0) << "some textures belong to one object only";
}

TEST(Scenes, CrowdSharesFewTexturesAmongManyDraws) {
  const SceneInfo i = scene_info(load_scene("crowd"));
  EXPECT_GE(i.draws, 300u);
  EXPECT_LE(i.textures, 8u);
  EXPECT_GE(i.max_sharing, 60);
}

TEST(Scenes, UnknownSceneIsAnError) {
  try {
    load_scene("no-such-scene");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown scene 'no-such-scene'"), std::string::npos);
  }
  EXPECT_THROW(load_scene(""), Error);
  // A model file's path that is not there is a missing file, not an unknown scene.
  const std::string m = test::message_of([] { (void)load_scene("/no/such/model.obj"); });
  EXPECT_NE(m.find("cannot load '/no/such/model.obj': no such file"), std::string::npos) << m;
  EXPECT_THROW(load_scene("/no/such/model.obj"), NotFoundError);
}

}  // namespace
}  // namespace oovr
