#include "oovr/scene/texture.h"

#include <stb_image.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <utility>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/limits.h"
#include "oovr/core/text.h"

namespace oovr {

uint64_t Texture::bytes() const {
  uint64_t b = 0;
  for (const auto& l : levels) b += uint64_t(l.width) * l.height * 4;
  return b;
}

static MipLevel downsample(const MipLevel& src) {
  MipLevel dst;
  dst.width = src.width > 1 ? src.width / 2 : 1;
  dst.height = src.height > 1 ? src.height / 2 : 1;
  dst.rgba.resize(size_t(dst.width) * dst.height * 4);
  for (int y = 0; y < dst.height; ++y)
    for (int x = 0; x < dst.width; ++x) {
      const int x0 = std::min(2 * x, src.width - 1), x1 = std::min(2 * x + 1, src.width - 1);
      const int y0 = std::min(2 * y, src.height - 1), y1 = std::min(2 * y + 1, src.height - 1);
      const uint8_t* a = &src.rgba[(size_t(y0) * src.width + x0) * 4];
      const uint8_t* b = &src.rgba[(size_t(y0) * src.width + x1) * 4];
      const uint8_t* c = &src.rgba[(size_t(y1) * src.width + x0) * 4];
      const uint8_t* d = &src.rgba[(size_t(y1) * src.width + x1) * 4];
      uint8_t* o = &dst.rgba[(size_t(y) * dst.width + x) * 4];
      for (int k = 0; k < 4; ++k) o[k] = uint8_t((a[k] + b[k] + c[k] + d[k] + 2) / 4);
    }
  return dst;
}

void build_mip_chain(Texture& t) {
  if (t.levels.empty()) return;
  t.levels.resize(1);
  while (t.levels.back().width > 1 || t.levels.back().height > 1) t.levels.push_back(downsample(t.levels.back()));
}

Texture make_texture(std::string name, std::string source, int width, int height, std::vector<uint8_t> rgba, Wrap wrap,
                     bool mipmapped) {
  Texture t;
  t.name = std::move(name);
  t.source = std::move(source);
  t.wrap = wrap;
  t.mipmapped = mipmapped;
  MipLevel base;
  base.width = width;
  base.height = height;
  base.rgba = std::move(rgba);
  for (size_t i = 3; i < base.rgba.size() && t.opaque; i += 4) t.opaque = base.rgba[i] == 255;
  t.levels.push_back(std::move(base));
  if (mipmapped) build_mip_chain(t);
  return t;
}

static bool is_sgi_name(const std::string& name) {
  const std::string ext = lower_extension(name);
  return ext == ".rgb" || ext == ".rgba" || ext == ".sgi" || ext == ".bw" || ext == ".int" || ext == ".inta";
}

// stb_image reads past the end of a TGA as zeros: a truncated file would
// become a texture of black texels. Its pixel data (raw, or run-length
// packets) must fit in the file.
static void check_tga_data(const uint8_t* b, size_t size, const std::string& name, int w, int h) {
  const auto truncated = [&] { throw Error("cannot decode image '" + name + "': the TGA file is truncated"); };
  if (size < 18) truncated();
  const int type = b[2], bpp = b[16];
  const size_t cmap_len = size_t(b[5]) | (size_t(b[6]) << 8), cmap_bits = b[7];
  const size_t start = 18 + size_t(b[0]) + (b[1] ? cmap_len * ((cmap_bits + 7) / 8) : 0);
  const size_t pixel = size_t(bpp + 7) / 8, pixels = size_t(w) * size_t(h);
  if (start > size || pixel == 0) truncated();
  if (type >= 1 && type <= 3) {
    if ((size - start) / pixel < pixels) truncated();
  } else if (type >= 9 && type <= 11) {
    size_t at = start, done = 0;
    while (done < pixels) {
      if (at >= size) truncated();
      const size_t count = size_t(b[at] & 0x7f) + 1;
      const size_t data = (b[at] & 0x80) ? pixel : count * pixel;
      ++at;
      if (data > size - at) truncated();
      at += data;
      done += count;
    }
  }
}

MipLevel decode_image(const uint8_t* bytes, size_t size, const std::string& name) {
  if (is_sgi_name(name)) return decode_sgi(bytes, size, name);
  if (size > size_t(std::numeric_limits<int>::max())) throw Error("image '" + name + "' is too large");
  int w = 0, h = 0, n = 0;
  // The size the header declares, checked before anything is allocated.
  if (stbi_info_from_memory(bytes, int(size), &w, &h, &n)) {
    const InputLimits& lim = InputLimits::get();
    if (w <= 0 || h <= 0)
      throw Error("cannot decode image '" + name + "': it declares " + std::to_string(w) + "x" + std::to_string(h) + " texels");
    check_limit(uint64_t(std::max(w, h)), uint64_t(lim.image_side), "image_side", "image '" + name + "'", "texels on a side");
    check_limit(uint64_t(w) * uint64_t(h), lim.image_texels, "image_texels", "image '" + name + "'", "texels");
    if (lower_extension(name) == ".tga") check_tga_data(bytes, size, name, w, h);
  }
  stbi_uc* data = stbi_load_from_memory(bytes, int(size), &w, &h, &n, 4);
  if (!data) {
    const char* why = stbi_failure_reason();
    throw Error("cannot decode image '" + name + "': " + (why ? why : "unknown error"));
  }
  MipLevel l;
  l.width = w;
  l.height = h;
  // Image files store the top row first; textures keep OpenGL's convention
  // (row 0 at t = 0, the bottom of the image), so rows are flipped here.
  const size_t row = size_t(w) * 4;
  l.rgba.resize(row * size_t(h));
  for (int y = 0; y < h; ++y) std::memcpy(&l.rgba[row * size_t(h - 1 - y)], data + row * size_t(y), row);
  stbi_image_free(data);
  return l;
}

MipLevel load_image_file(const std::string& path) {
  const std::string bytes = read_input_file(path, "image", InputLimits::get().file_bytes);
  return decode_image(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path);
}

}  // namespace oovr
