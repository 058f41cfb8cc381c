// Texture sampling: mip chain construction and level-of-detail selection on
// a known gradient of texel density.
#include <gtest/gtest.h>

#include "oovr/core/error.h"
#include "test_util.h"

namespace oovr {
namespace {

TEST(Mip, ChainAveragesAndFloorsOddSizes) {
  std::vector<uint8_t> px(5 * 3 * 4);
  for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 7 % 256);
  const Texture t = make_texture("t", "t", 5, 3, px);
  ASSERT_EQ(t.levels.size(), 3u);  // 5x3, 2x1, 1x1
  EXPECT_EQ(t.levels[1].width, 2);
  EXPECT_EQ(t.levels[1].height, 1);
  EXPECT_EQ(t.levels[2].width, 1);
  // Level 1 texel (0,0) = rounded mean of level 0 texels (0,0) (1,0) (0,1) (1,1).
  const auto at = [&](int x, int y, int c) { return int(px[size_t((y * 5 + x) * 4 + c)]); };
  for (int c = 0; c < 4; ++c)
    EXPECT_EQ(int(t.levels[1].rgba[size_t(c)]), (at(0, 0, c) + at(1, 0, c) + at(0, 1, c) + at(1, 1, c) + 2) / 4);
  EXPECT_EQ(t.bytes(), uint64_t((15 + 2 + 1) * 4));
}

// A 256x256 texture whose level k is filled with a solid colour unique to k.
Texture level_coded_texture() {
  Texture t = make_texture("levels", "levels", 256, 256, std::vector<uint8_t>(256 * 256 * 4, 0));
  for (size_t k = 0; k < t.levels.size(); ++k)
    for (size_t i = 0; i < t.levels[k].rgba.size(); i += 4) {
      t.levels[k].rgba[i] = uint8_t(k * 20);
      t.levels[k].rgba[i + 1] = 255;
      t.levels[k].rgba[i + 2] = 0;
      t.levels[k].rgba[i + 3] = 255;
    }
  return t;
}

// Renders a 64x64 quad whose texture coordinates span [0, repeats], so each
// pixel covers 256 * repeats / 64 texels along both axes.
FrameOutput render_quad(float repeats, int aniso = 1, float v_repeats = -1) {
  if (v_repeats < 0) v_repeats = repeats;
  Scene s = test::triangle_scene({{0, 0}, {64, 0}, {64, 64}, {0, 64}}, {0, 1, 2, 0, 2, 3});
  s.meshes[0].vertices[1].uv = {repeats, 0};
  s.meshes[0].vertices[2].uv = {repeats, v_repeats};
  s.meshes[0].vertices[3].uv = {0, v_repeats};
  s.textures.push_back(level_coded_texture());
  s.materials[0] = Material::textured("levels", 0);
  PipelineSettings p = test::exact_settings();
  p.max_anisotropy = aniso;
  p.texture_format = TextureFormat::rgba8;  // the line arithmetic below is RGBA8's
  return render_frame(s, test::ortho_view(64, 64), p);
}

TEST(Mip, LevelFollowsTexelsPerPixel) {
  // texels per pixel = 4 * repeats; lambda = log2 of it.
  const struct {
    float repeats;
    int red;  // 20 * level, or a blend
  } cases[] = {
      {0.125f, 0},   // 0.5 texel per pixel: magnification, level 0
      {0.25f, 0},    // 1 texel per pixel: lambda 0
      {0.5f, 20},    // 2: level 1
      {1.0f, 40},    // 4: level 2
      {4.0f, 80},    // 16: level 4
      {64.0f, 160},  // 256: level 8 (1x1), the last level
  };
  for (const auto& c : cases) {
    const FrameOutput out = render_quad(c.repeats);
    EXPECT_EQ(int(out.colour.pixel(32, 32)[0]), c.red) << "repeats " << c.repeats;
  }
  // Halfway between levels 2 and 3 (lambda = 2.5): trilinear blend of 40 and 60.
  const FrameOutput mid = render_quad(std::sqrt(2.0f));
  EXPECT_NEAR(int(mid.colour.pixel(32, 32)[0]), 50, 1);
}

TEST(Mip, TraceRecordsLinesOfTheSelectedLevel) {
  const FrameOutput out = render_quad(1.0f);  // level 2: 64x64 texels
  ASSERT_FALSE(out.trace.tex_lines.empty());
  // Levels 0 and 1 hold (256*256 + 128*128) / 32 lines of 8x4 texels.
  const uint32_t level2_first = (256 * 256 + 128 * 128) / 32, level2_lines = 64 * 64 / 32;
  for (TexLine l : out.trace.tex_lines) {
    EXPECT_EQ(tex_line_texture(l), 0u);
    EXPECT_GE(tex_line_index(l), level2_first);
    EXPECT_LT(tex_line_index(l), level2_first + level2_lines);
  }
}

TEST(Mip, AnisotropicFilteringUsesTheMinorAxis) {
  // Footprint 16 texels across and 2 texels down: isotropic filtering picks
  // level 4 from the major axis; with 8 anisotropic taps lambda drops to
  // log2(16 / 8) = 1.
  const FrameOutput iso = render_quad(4.0f, 1, 0.5f);
  const FrameOutput aniso = render_quad(4.0f, 8, 0.5f);
  EXPECT_EQ(int(iso.colour.pixel(32, 32)[0]), 80);
  EXPECT_EQ(int(aniso.colour.pixel(32, 32)[0]), 20);
}

TEST(Mip, SettingsAreValidated) {
  PipelineSettings p;
  p.max_anisotropy = 0;
  EXPECT_THROW(p.validate(), Error);
  p.max_anisotropy = 16;
  p.line_bytes = 96;
  EXPECT_THROW(p.validate(), Error);
  p.line_bytes = 2048;
  EXPECT_THROW(p.validate(), Error);
}

}  // namespace
}  // namespace oovr
