// The SGI image decoder: verbatim and RLE, 1 to 4 channels, real TORCS
// textures, and clear errors for truncated or corrupt files.
#include <gtest/gtest.h>

#include <filesystem>

#include "game_data.h"
#include "oovr/core/error.h"
#include "oovr/scene/sources/torcs.h"
#include "oovr/scene/texture.h"

namespace oovr {
namespace {

void expect_test_image(const MipLevel& l, int w, int h, int channels) {
  ASSERT_EQ(l.width, w);
  ASSERT_EQ(l.height, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = &l.rgba[(size_t(y) * size_t(w) + size_t(x)) * 4];
      if (channels <= 2) {
        EXPECT_EQ(p[0], test::test_sgi_value(x, y, 0));
        EXPECT_EQ(p[1], p[0]);
        EXPECT_EQ(p[3], channels == 2 ? test::test_sgi_value(x, y, 1) : 255);
      } else {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], test::test_sgi_value(x, y, c)) << x << "," << y << " c" << c;
        EXPECT_EQ(p[3], channels == 4 ? test::test_sgi_value(x, y, 3) : 255);
      }
    }
}

TEST(Sgi, VerbatimAndRleDecodeTheSameImage) {
  for (int channels = 1; channels <= 4; ++channels)
    for (bool rle : {false, true}) {
      SCOPED_TRACE(std::to_string(channels) + " channels, " + (rle ? "RLE" : "verbatim"));
      const auto file = test::make_test_sgi(13, 5, channels, rle);
      expect_test_image(decode_sgi(file.data(), file.size(), "t.rgb"), 13, 5, channels);
    }
  // decode_image picks the SGI decoder by extension.
  const auto file = test::make_test_sgi(8, 8, 3, true);
  EXPECT_EQ(decode_image(file.data(), file.size(), "x.RGB").width, 8);
}

TEST(Sgi, EveryTruncationIsRefused) {
  for (bool rle : {false, true}) {
    const auto file = test::make_test_sgi(9, 4, 4, rle);
    for (size_t n = 0; n < file.size(); ++n) EXPECT_THROW(decode_sgi(file.data(), n, "t.rgb"), Error) << n << " bytes";
  }
}

TEST(Sgi, CorruptHeadersAndRunsAreRefused) {
  const auto good = test::make_test_sgi(9, 4, 3, true);
  auto bad = good;
  bad[0] = 0;  // magic
  EXPECT_THROW(decode_sgi(bad.data(), bad.size(), "t.rgb"), Error);
  bad = good;
  bad[3] = 3;  // bytes per channel
  EXPECT_THROW(decode_sgi(bad.data(), bad.size(), "t.rgb"), Error);
  bad = good;
  bad[11] = 9;  // channels
  EXPECT_THROW(decode_sgi(bad.data(), bad.size(), "t.rgb"), Error);
  bad = good;
  bad[6] = bad[7] = bad[8] = bad[9] = 0xff;  // 65535 x 65535: refused before allocating
  EXPECT_THROW(decode_sgi(bad.data(), bad.size(), "t.rgb"), Error);
  bad = good;
  bad[512] = 0x7f;  // first row starts far past the end
  EXPECT_THROW(decode_sgi(bad.data(), bad.size(), "t.rgb"), Error);
  bad = good;
  const size_t first_row = (size_t(bad[512]) << 24) | (size_t(bad[513]) << 16) | (size_t(bad[514]) << 8) | bad[515];
  bad[first_row] = 0xff;  // a literal run of 127 in a 9-pixel row
  EXPECT_THROW(decode_sgi(bad.data(), bad.size(), "t.rgb"), Error);
  try {
    decode_sgi(bad.data(), 100, "textures/some.rgb");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("textures/some.rgb"), std::string::npos) << "the message names the file";
  }
}

TEST(Sgi, DecodesTorcsTextures) {
  const std::filesystem::path dir = std::filesystem::path(torcs_directory()) / "data" / "textures";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "torcs-data is not installed (" << dir << ")";
  int decoded = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".rgb") continue;
    const MipLevel l = load_image_file(e.path().string());
    EXPECT_GT(l.width, 0);
    EXPECT_EQ(l.rgba.size(), size_t(l.width) * size_t(l.height) * 4);
    ++decoded;
  }
  EXPECT_GT(decoded, 50);
}

}  // namespace
}  // namespace oovr
