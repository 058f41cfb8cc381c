#include "oovr/pipeline/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"

namespace oovr {

namespace {

// stb encodes into memory; write_output_file then writes the bytes checked
// (a full disk is an error, not a silently short file).
void append_bytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}

}  // namespace

std::string encode_png(const Image& img) {
  const int stride = img.width * 4;
  if (img.width <= 0 || img.height <= 0) throw Error("cannot encode an empty image as PNG");
  // Point at the last row with a negative stride: PNG rows go top-down.
  const uint8_t* last = img.rgba.data() + size_t(img.height - 1) * size_t(stride);
  std::string bytes;
  if (!stbi_write_png_to_func(append_bytes, &bytes, img.width, img.height, 4, last, -stride))
    throw Error("cannot encode a " + std::to_string(img.width) + "x" + std::to_string(img.height) + " image as PNG");
  return bytes;
}

void write_png(const Image& img, const std::string& path) {
  std::string bytes;
  try {
    bytes = encode_png(img);
  } catch (const Error& e) {
    throw Error("cannot write PNG '" + path + "': " + e.what());
  }
  write_output_file(path, bytes, "image");
}

void check_image_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg")
    throw Error("cannot write '" + path + "': unsupported image type '" + ext + "' (use .png or .jpg)");
  check_output_path(path, "image");
}

void write_image(const Image& img, const std::string& path) {
  check_image_path(path);
  if (lower_extension(path) == ".png") return write_png(img, path);
  // stb writes top-down; flip into a copy.
  std::vector<uint8_t> rgb(size_t(img.width) * size_t(img.height) * 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* p = img.pixel(x, img.height - 1 - y);
      uint8_t* o = &rgb[(size_t(y) * size_t(img.width) + size_t(x)) * 3];
      o[0] = p[0];
      o[1] = p[1];
      o[2] = p[2];
    }
  std::string bytes;
  if (img.width <= 0 || img.height <= 0 ||
      !stbi_write_jpg_to_func(append_bytes, &bytes, img.width, img.height, 3, rgb.data(), 90))
    throw Error("cannot encode JPEG '" + path + "'");
  write_output_file(path, bytes, "image");
}

Image read_png(const std::string& path) {
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 4);
  if (!data) throw Error("cannot read image '" + path + "'");
  Image img(w, h);
  for (int y = 0; y < h; ++y) std::memcpy(img.pixel(0, h - 1 - y), data + size_t(y) * w * 4, size_t(w) * 4);
  stbi_image_free(data);
  return img;
}

double psnr_rgb(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) throw Error("cannot compare images of different sizes");
  double sum = 0;
  const size_t n = size_t(a.width) * a.height;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = double(a.rgba[i * 4 + c]) - double(b.rgba[i * 4 + c]);
      sum += d * d;
    }
  if (sum == 0) return std::numeric_limits<double>::infinity();
  const double mse = sum / double(n * 3);
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

}  // namespace oovr
