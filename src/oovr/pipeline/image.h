// RGBA8 images. Rows are stored bottom-up (row 0 is the bottom of the frame),
// the convention of OpenGL window coordinates and glReadPixels; PNG files are
// written top-down.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oovr/core/uninitialised.h"

namespace oovr {

struct Image {
  int width = 0, height = 0;
  UninitialisedVector<uint8_t> rgba;

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(size_t(w) * h * 4, 0) {}
  // Pixels left as the allocation found them, for a writer that sets every
  // one (the renderer's tiles).
  struct Unset {};
  Image(int w, int h, Unset) : width(w), height(h), rgba(size_t(w) * h * 4) {}
  uint8_t* pixel(int x, int y) { return &rgba[(size_t(y) * width + x) * 4]; }
  const uint8_t* pixel(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

// The image as PNG file bytes (top row first).
std::string encode_png(const Image& img);
// Writes a PNG (top row first). Throws Error naming the file on failure.
void write_png(const Image& img, const std::string& path);
// Writes PNG or JPEG (quality 90) by the file's extension (.png, .jpg,
// .jpeg); any other extension is an Error.
void write_image(const Image& img, const std::string& path);
// Throws the Error write_image would for an unsupported extension, so a
// command can refuse a bad --out before doing any work.
void check_image_path(const std::string& path);  // the type, and that the path can be written (core/files.h)
// Reads a PNG written by write_png (or any 8-bit image stb_image decodes).
Image read_png(const std::string& path);

// Peak signal-to-noise ratio over the RGB channels, in dB (infinite when
// identical). Images must have the same size.
double psnr_rgb(const Image& a, const Image& b);

}  // namespace oovr
