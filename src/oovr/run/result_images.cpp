#include "oovr/run/result_images.h"

#include <algorithm>
#include <cmath>

namespace oovr {

namespace {

// Sixteen distinct hues (GPMs beyond 16 reuse them).
const uint8_t palette[16][3] = {{230, 25, 75},  {60, 180, 75},   {0, 130, 200},  {255, 225, 25},  {245, 130, 48}, {145, 30, 180},
                                {70, 240, 240}, {240, 50, 230},  {210, 245, 60}, {250, 190, 212}, {0, 128, 128},  {220, 190, 255},
                                {170, 110, 40}, {255, 250, 200}, {128, 0, 0},    {170, 255, 195}};

}  // namespace

std::string gpm_colour(int gpm) {
  const uint8_t* c = palette[gpm % 16];
  static const char* hex = "0123456789abcdef";
  std::string s = "#";
  for (int i = 0; i < 3; ++i) {
    s += hex[c[i] >> 4];
    s += hex[c[i] & 15];
  }
  return s;
}

Image gpm_image(const FrameOutput& out, const SchemeResult& r) {
  Image img(out.colour.width, out.colour.height);
  const int tiles_x = out.trace.tiles_x;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* src = out.colour.pixel(x, y);
      uint8_t* dst = img.pixel(x, y);
      dst[3] = 255;
      const uint32_t obj = out.object_id[size_t(y) * size_t(img.width) + size_t(x)];
      if (obj == kNoObject) continue;
      const uint32_t tile = uint32_t(y / kTileSize) * uint32_t(tiles_x) + uint32_t(x / kTileSize);
      const int gpm = r.owner_of(obj, tile);
      if (gpm < 0) continue;
      const float lum = (0.3f * src[0] + 0.59f * src[1] + 0.11f * src[2]) / 255.0f;
      for (int c = 0; c < 3; ++c) dst[c] = uint8_t(palette[gpm % 16][c] * (0.35f + 0.65f * lum));
    }
  return img;
}

Image traffic_image(const FrameOutput& out, const SchemeResult& r) {
  Image img(out.colour.width, out.colour.height);
  uint64_t most = 1;
  for (uint64_t b : r.tile_inter_gpm_bytes) most = std::max(most, b);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const size_t tile = size_t(y / kTileSize) * size_t(out.trace.tiles_x) + size_t(x / kTileSize);
      const float v = std::sqrt(float(r.tile_inter_gpm_bytes[tile]) / float(most));
      uint8_t* p = img.pixel(x, y);
      p[0] = uint8_t(255 * std::min(1.0f, v * 2));
      p[1] = uint8_t(255 * std::max(0.0f, v * 2 - 1));
      p[2] = 0;
      p[3] = 255;
    }
  return img;
}

}  // namespace oovr
