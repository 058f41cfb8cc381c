// Textures: RGBA8 images with full mip chains. The chain is built once, here,
// and both oovr's pipeline and the reference renderer use exactly these texels
// (the reference uploads every level), so filtering is compared on equal data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace oovr {

struct MipLevel {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4 bytes, row 0 at t = 0 (OpenGL's convention)
};

enum class Wrap : uint8_t { repeat, clamp_to_edge };

struct Texture {
  std::string name;    // display name (file name or procedural name)
  std::string source;  // identity for de-duplication: absolute path or generator key
  Wrap wrap = Wrap::repeat;
  // Sampled with trilinear mip filtering when true; bilinear on level 0 only
  // when false (e.g. Quake 3 lightmaps are not mip-mapped).
  bool mipmapped = true;
  // Every base texel has alpha 255 (set by make_texture). A block-compressed
  // store keeps such an image in BC1 and one with alpha in BC3.
  bool opaque = true;
  // Whether a block-compressed store compresses it: engines upload
  // lightmaps and deluxe maps uncompressed (ioquake3's R_LoadLightmaps,
  // DarkPlaces' lightmap textures).
  bool compress = true;
  std::vector<MipLevel> levels;  // levels[0] is the base image

  int width() const { return levels.empty() ? 0 : levels[0].width; }
  int height() const { return levels.empty() ? 0 : levels[0].height; }
  // Bytes of all levels (RGBA8).
  uint64_t bytes() const;
};

// Replaces t.levels with levels[0] followed by its full chain down to 1x1.
// Each texel of level n+1 is the rounded mean of the (up to) 2x2 texels of
// level n it covers; odd sizes use floor(size / 2) as OpenGL does.
void build_mip_chain(Texture& t);

// Makes a texture from RGBA8 pixels and builds its mip chain when mipmapped.
Texture make_texture(std::string name, std::string source, int width, int height, std::vector<uint8_t> rgba,
                     Wrap wrap = Wrap::repeat, bool mipmapped = true);

// Decodes an image file (PNG, JPEG, TGA, BMP via stb_image; SGI .rgb/.rgba/
// .sgi/.bw by oovr's decoder) into RGBA8. Throws Error naming the file when it
// cannot be read or decoded.
MipLevel load_image_file(const std::string& path);
// The same for an image held in memory; `name` is used in messages and to
// recognise SGI images by extension.
MipLevel decode_image(const uint8_t* data, size_t size, const std::string& name);
// Decodes an SGI image (magic 474; verbatim or RLE; 1 or 2 bytes per channel;
// 1 to 4 channels). Throws Error naming `name` and what is wrong.
MipLevel decode_sgi(const uint8_t* data, size_t size, const std::string& name);

}  // namespace oovr
