// Writers for small synthetic game files (BSP, SGI) used by the tests and
// the fuzzers' seed corpora, and helpers to find Debian's game data.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "oovr/scene/formats/bsp.h"
#include "oovr/scene/sources/nexuiz.h"
#include "oovr/scene/sources/openarena.h"
#include "oovr/scene/sources/torcs.h"

namespace oovr::test {

inline void put32(std::vector<uint8_t>& b, size_t at, int32_t v) { std::memcpy(&b[at], &v, 4); }
inline void putf(std::vector<uint8_t>& b, size_t at, float v) { std::memcpy(&b[at], &v, 4); }

// A valid IBSP 46 file: shader 0 "textures/test/wall", one polygon face (a
// quad, two triangles), one 3x3 patch face, one billboard, one lightmap,
// and an entity lump with one spawn point.
inline std::vector<uint8_t> make_test_bsp() {
  struct Lump {
    std::vector<uint8_t> data;
  };
  Lump lumps[17];
  const std::string ents =
      "{\n\"classname\" \"worldspawn\"\n}\n{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"16 32 24\"\n\"angle\" "
      "\"90\"\n}\n";
  lumps[0].data.assign(ents.begin(), ents.end());
  lumps[0].data.push_back(0);
  lumps[1].data.resize(72 * 1, 0);
  std::memcpy(lumps[1].data.data(), "textures/test/wall", 18);
  // 4 quad vertices + 9 patch control points + 4 billboard vertices.
  std::vector<std::array<float, 7>> v;  // x y z s t lu lv
  v.push_back({0, 0, 0, 0, 0, 0, 0});
  v.push_back({64, 0, 0, 1, 0, 1, 0});
  v.push_back({64, 0, 64, 1, 1, 1, 1});
  v.push_back({0, 0, 64, 0, 1, 0, 1});
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      v.push_back({float(i * 32), 64.0f + (i == 1 ? 16.0f : 0.0f), float(j * 32), i / 2.0f, j / 2.0f, 0, 0});
  for (int k = 0; k < 4; ++k) v.push_back({0, 0, 0, 0, 0, 0, 0});
  lumps[10].data.resize(v.size() * 44, 0);
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 7; ++k) putf(lumps[10].data, i * 44 + size_t(k) * 4, v[i][size_t(k)]);
  for (size_t i = 0; i < 4; ++i) putf(lumps[10].data, i * 44 + 32, -1.0f);  // normal -y
  for (size_t i = 4; i < 13; ++i) putf(lumps[10].data, i * 44 + 32, 1.0f);  // normal +y
  // Quake 3 order: clockwise seen from the front (the -y side).
  const int32_t meshverts[6] = {0, 2, 1, 0, 3, 2};
  lumps[11].data.resize(sizeof meshverts);
  std::memcpy(lumps[11].data.data(), meshverts, sizeof meshverts);
  lumps[14].data.assign(size_t(kBspLightmapSize) * kBspLightmapSize * 3, 128);
  lumps[13].data.resize(104 * 3, 0);
  auto face = [&](size_t f, int type, int first, int n, int mv, int nmv, int lm, int w, int h) {
    const size_t at = f * 104;
    put32(lumps[13].data, at + 0, 0);
    put32(lumps[13].data, at + 8, type);
    put32(lumps[13].data, at + 12, first);
    put32(lumps[13].data, at + 16, n);
    put32(lumps[13].data, at + 20, mv);
    put32(lumps[13].data, at + 24, nmv);
    put32(lumps[13].data, at + 28, lm);
    putf(lumps[13].data, at + 88, -1.0f);  // normal -y
    put32(lumps[13].data, at + 96, w);
    put32(lumps[13].data, at + 100, h);
  };
  face(0, kBspPolygon, 0, 4, 0, 6, 0, 0, 0);
  face(1, kBspPatch, 4, 9, 0, 0, -1, 3, 3);
  face(2, kBspBillboard, 13, 4, 0, 0, -1, 0, 0);
  std::vector<uint8_t> out(8 + 17 * 8, 0);
  std::memcpy(out.data(), "IBSP", 4);
  put32(out, 4, 46);
  for (int l = 0; l < 17; ++l) {
    put32(out, size_t(8 + l * 8), int32_t(out.size()));
    put32(out, size_t(12 + l * 8), int32_t(lumps[l].data.size()));
    out.insert(out.end(), lumps[l].data.begin(), lumps[l].data.end());
  }
  return out;
}

// Offset of face f's field `field` (byte offset within the 104-byte face) in
// a file made by make_test_bsp.
inline size_t test_bsp_face_field(const std::vector<uint8_t>& bsp, int f, int field) {
  int32_t off = 0;
  std::memcpy(&off, &bsp[8 + 13 * 8], 4);
  return size_t(off) + size_t(f) * 104 + size_t(field);
}

// Pixel (x, y, channel c) of the test SGI images: constant over groups of
// four pixels in a row, so that RLE files hold repeat runs.
inline uint8_t test_sgi_value(int x, int y, int c) { return uint8_t(((x / 4) * 7 + y * 13 + c * 50) & 255); }

// An SGI image (magic 474) of w x h pixels and `channels` channels, one byte
// per channel, verbatim or RLE (groups of four pixels alternate literal and
// repeat runs).
inline std::vector<uint8_t> make_test_sgi(int w, int h, int channels, bool rle) {
  std::vector<uint8_t> out(512, 0);
  out[0] = 0x01;
  out[1] = 0xda;
  out[2] = rle ? 1 : 0;
  out[3] = 1;
  out[5] = 3;
  out[6] = uint8_t(w >> 8);
  out[7] = uint8_t(w);
  out[8] = uint8_t(h >> 8);
  out[9] = uint8_t(h);
  out[11] = uint8_t(channels);
  if (!rle) {
    for (int c = 0; c < channels; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) out.push_back(test_sgi_value(x, y, c));
    return out;
  }
  const size_t rows = size_t(h) * size_t(channels);
  const size_t tables = out.size();
  out.resize(out.size() + rows * 8, 0);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y) {
      const size_t r = size_t(c) * size_t(h) + size_t(y);
      const uint32_t start = uint32_t(out.size());
      for (int x = 0; x < w; x += 4) {
        const int n = std::min(4, w - x);
        if ((x / 4) % 2 == 0) {
          out.push_back(uint8_t(0x80 | n));
          for (int k = 0; k < n; ++k) out.push_back(test_sgi_value(x + k, y, c));
        } else {
          out.push_back(uint8_t(n));
          out.push_back(test_sgi_value(x, y, c));
        }
      }
      out.push_back(0);
      const uint32_t len = uint32_t(out.size()) - start;
      for (int k = 0; k < 4; ++k) {
        out[tables + r * 4 + size_t(k)] = uint8_t(start >> (24 - 8 * k));
        out[tables + rows * 4 + r * 4 + size_t(k)] = uint8_t(len >> (24 - 8 * k));
      }
    }
  return out;
}

// The game data the tests use, where the loaders look for it (Debian's
// paths unless OOVR_OPENARENA_DIR / OOVR_NEXUIZ_DIR / OOVR_TORCS_DIR say otherwise).
inline bool have_openarena() { return std::filesystem::exists(openarena_directory() + "/pak0.pk3"); }
inline bool have_nexuiz() { return std::filesystem::exists(nexuiz_directory() + "/data.pk3"); }
inline bool have_torcs() { return std::filesystem::exists(torcs_directory() + "/tracks/road/spring/spring.acc"); }

}  // namespace oovr::test
