// SMP stereo: geometry processed once and projected into both eyes gives
// exactly the images (and work) of two separate mono renders, and nothing
// drawn for one eye spills into the other eye's half of the frame.
#include <gtest/gtest.h>

#include <cstring>

#include "oovr/scene/builtin.h"
#include "test_util.h"

namespace oovr {
namespace {

// One eye alone, drawn into its own viewport of the same frame: the
// multi-pass way of rendering stereo (one pass per eye).
StereoView mono_view(const StereoView& stereo, int eye) {
  StereoView m;
  m.eyes = 1;
  m.frame_width = stereo.frame_width;
  m.frame_height = stereo.frame_height;
  m.viewport[0] = stereo.viewport[eye];
  m.clip_from_world[0] = stereo.clip_from_world[eye];
  m.eye_position[0] = stereo.eye_position[eye];
  return m;
}

class StereoEqualsMono : public ::testing::TestWithParam<std::string> {};

TEST_P(StereoEqualsMono, ImagesAndCounts) {
  const Scene scene = BuiltinScenes::find(GetParam())->make();
  StereoRig rig;
  rig.eye_width = 200;  // not a multiple of the tile size: tiles straddle the eyes
  rig.eye_height = 160;
  for (int frame : {0, 45}) {
    const StereoView stereo = make_stereo_view(scene.camera, frame, rig);
    const FrameOutput s = render_frame(scene, stereo, test::exact_settings(2));
    uint64_t stereo_covered[2] = {0, 0}, mono_covered[2] = {0, 0};
    for (const auto& t : s.trace.tiles) stereo_covered[t.eye] += t.covered;
    for (int e = 0; e < 2; ++e) {
      const FrameOutput m = render_frame(scene, mono_view(stereo, e), test::exact_settings(2));
      for (const auto& t : m.trace.tiles) mono_covered[e] += t.covered;
      int differing = 0;
      for (int y = 0; y < rig.eye_height; ++y)
        for (int x = 0; x < rig.eye_width; ++x)
          differing += std::memcmp(s.colour.pixel(e * rig.eye_width + x, y), m.colour.pixel(e * rig.eye_width + x, y), 4) != 0;
      EXPECT_EQ(differing, 0) << "eye " << e << " frame " << frame;
      EXPECT_EQ(stereo_covered[e], mono_covered[e]) << "eye " << e << " frame " << frame;
      for (size_t o = 0; o < scene.objects.size(); ++o) {
        EXPECT_EQ(s.trace.objects[o].setup[e], m.trace.objects[o].setup[0]);
        EXPECT_EQ(s.trace.objects[o].vertices, m.trace.objects[o].vertices) << "SMP transforms each vertex once for both eyes";
      }
    }
    // Every tile record of an eye lies in tiles that overlap its viewport.
    ASSERT_FALSE(s.trace.tiles.empty());
    for (const auto& t : s.trace.tiles) {
      const int x0 = t.tile_x * kTileSize, x1 = x0 + kTileSize;
      EXPECT_TRUE(x1 > stereo.viewport[t.eye].x && x0 < stereo.viewport[t.eye].x + stereo.viewport[t.eye].width);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Builtin, StereoEqualsMono, ::testing::Values("courtyard", "crowd"));

TEST(Stereo, EyesAreSeparatedByTheInterpupillaryDistance) {
  CameraPath path;
  path.frames.push_back({{1, 2, 3}, {1, 2, -7}, {0, 1, 0}});
  StereoRig rig;
  const StereoView v = make_stereo_view(path, 0, rig);
  EXPECT_NEAR(v.eye_position[kLeft].x, 1 - 0.032f, 1e-6);
  EXPECT_NEAR(v.eye_position[kRight].x, 1 + 0.032f, 1e-6);
  EXPECT_EQ(v.viewport[kRight].x, rig.eye_width);
  EXPECT_EQ(v.frame_width, 2 * rig.eye_width);
}

TEST(Stereo, ResolutionParsing) {
  EXPECT_EQ(parse_frame_resolution("1280x1024").eye_width, 640);
  EXPECT_EQ(parse_eye_resolution("640x480").eye_width, 640);
  EXPECT_THROW(parse_frame_resolution("641x480"), Error);
  EXPECT_THROW(parse_frame_resolution("640"), Error);
  EXPECT_THROW(parse_frame_resolution("0x480"), Error);
  EXPECT_THROW(parse_frame_resolution("640x480x2"), Error);
  EXPECT_THROW(parse_frame_resolution("-640x480"), Error);
  EXPECT_THROW(parse_frame_resolution("99999x480"), Error);
}

}  // namespace
}  // namespace oovr
