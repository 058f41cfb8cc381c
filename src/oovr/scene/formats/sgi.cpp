// SGI image decoder (the SGI Image File Format, Haeberli 1988), for TORCS's
// .rgb textures, which stb_image cannot read. Every size and offset is checked
// against the data before use, so a truncated or corrupt file is an Error,
// never an out-of-bounds read or an unbounded allocation.
#include <cstring>

#include "oovr/core/error.h"
#include "oovr/scene/texture.h"

namespace oovr {
namespace {

constexpr size_t kHeaderBytes = 512;
constexpr uint64_t kMaxPixels = uint64_t(1) << 26;  // 64 Mpixel: far above any texture

uint16_t be16(const uint8_t* p) { return uint16_t((p[0] << 8) | p[1]); }
uint32_t be32(const uint8_t* p) { return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3]; }

}  // namespace

MipLevel decode_sgi(const uint8_t* data, size_t size, const std::string& name) {
  const auto fail = [&](const std::string& why) { return Error("cannot decode SGI image '" + name + "': " + why); };
  if (size < kHeaderBytes) throw fail("file is " + std::to_string(size) + " bytes, shorter than the 512-byte header");
  if (be16(data) != 474) throw fail("bad magic number (not an SGI image)");
  const int storage = data[2], bpc = data[3];
  const int dimension = be16(data + 4);
  const uint32_t xsize = be16(data + 6);
  const uint32_t ysize = dimension >= 2 ? be16(data + 8) : 1;
  const uint32_t zsize = dimension >= 3 ? be16(data + 10) : 1;
  if (storage != 0 && storage != 1) throw fail("unknown storage type " + std::to_string(storage));
  if (bpc != 1 && bpc != 2) throw fail("unsupported " + std::to_string(bpc) + " bytes per channel");
  if (dimension < 1 || dimension > 3) throw fail("bad dimension " + std::to_string(dimension));
  if (xsize == 0 || ysize == 0 || zsize == 0) throw fail("empty image");
  if (zsize > 4) throw fail("unsupported " + std::to_string(zsize) + " channels");
  if (uint64_t(xsize) * ysize > kMaxPixels) throw fail("image too large");

  // Planar channels, rows bottom to top (the same as oovr's textures).
  const size_t row_bytes = size_t(xsize) * size_t(bpc);
  std::vector<uint8_t> planes(row_bytes * ysize * zsize);
  if (storage == 0) {
    if (size - kHeaderBytes < planes.size()) throw fail("pixel data truncated");
    std::memcpy(planes.data(), data + kHeaderBytes, planes.size());
  } else {
    const size_t rows = size_t(ysize) * zsize;
    if ((size - kHeaderBytes) / 8 < rows) throw fail("RLE offset tables truncated");
    const uint8_t* starts = data + kHeaderBytes;
    const uint8_t* lengths = starts + rows * 4;
    for (size_t r = 0; r < rows; ++r) {
      const uint64_t start = be32(starts + r * 4), length = be32(lengths + r * 4);
      if (start > size || length > size - start) throw fail("RLE row " + std::to_string(r) + " lies outside the file");
      const uint8_t* in = data + start;
      const uint8_t* end = in + length;
      uint8_t* out = planes.data() + r * row_bytes;
      size_t written = 0;  // samples
      auto read_sample = [&](const uint8_t*& p) -> uint16_t {
        if (end - p < bpc) throw fail("RLE row " + std::to_string(r) + " ends inside a run");
        const uint16_t v = bpc == 1 ? p[0] : be16(p);
        p += bpc;
        return v;
      };
      auto put = [&](uint16_t v) {
        if (written >= xsize) throw fail("RLE row " + std::to_string(r) + " is longer than the image width");
        if (bpc == 1) out[written] = uint8_t(v);
        else {
          out[written * 2] = uint8_t(v >> 8);
          out[written * 2 + 1] = uint8_t(v);
        }
        ++written;
      };
      for (;;) {
        const uint16_t code = read_sample(in);
        const int count = code & 0x7f;
        if (count == 0) break;
        if (code & 0x80) {
          for (int i = 0; i < count; ++i) put(read_sample(in));
        } else {
          const uint16_t v = read_sample(in);
          for (int i = 0; i < count; ++i) put(v);
        }
      }
      if (written != xsize) throw fail("RLE row " + std::to_string(r) + " is shorter than the image width");
    }
  }

  MipLevel l;
  l.width = int(xsize);
  l.height = int(ysize);
  l.rgba.resize(size_t(xsize) * ysize * 4);
  const size_t plane = row_bytes * ysize;
  auto sample = [&](uint32_t z, size_t pixel) -> uint8_t {
    return planes[z * plane + pixel * size_t(bpc)];  // high byte of 16-bit samples
  };
  for (size_t p = 0; p < size_t(xsize) * ysize; ++p) {
    uint8_t* o = &l.rgba[p * 4];
    if (zsize <= 2) {
      o[0] = o[1] = o[2] = sample(0, p);
      o[3] = zsize == 2 ? sample(1, p) : 255;
    } else {
      o[0] = sample(0, p);
      o[1] = sample(1, p);
      o[2] = sample(2, p);
      o[3] = zsize == 4 ? sample(3, p) : 255;
    }
  }
  return l;
}

}  // namespace oovr
