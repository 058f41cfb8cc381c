// The tiled layout of a texture in memory: one cache line holds a
// block_w x block_h block of texels; a level's blocks are row-major; levels
// follow each other. The sampler records line indices in this layout and the
// memory system gives them addresses, so both use these functions.
//
// How many texels a line holds depends on the storage format: 4 bytes per
// texel in RGBA8; in BC1 and BC3 (S3TC/DXT1 and DXT5) a 4x4 texel block is
// 8 or 16 bytes, so a 128-byte line holds 16x16 or 16x8 texels. oovr samples
// the decoded texels either way: the format changes footprint and traffic,
// not the image.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "oovr/scene/texture.h"

namespace oovr {

enum class TextureFormat : uint8_t {
  rgba8,  // 4 bytes per texel, every texture
  bc1,    // 8 bytes per 4x4 block, every compressible texture
  bc3,    // 16 bytes per 4x4 block, every compressible texture
  bc,     // as the games: BC1 for opaque images, BC3 for images with alpha
};
const char* texture_format_name(TextureFormat f);
// Throws Error for an unknown name.
TextureFormat parse_texture_format(const std::string& name);

// Cells of `cell_bytes` (a texel or a 4x4 block) per line, as a near-square
// block: the wider side first (e.g. 32 cells -> 8x4).
inline void cells_per_line(uint32_t line_bytes, uint32_t cell_bytes, int& w, int& h) {
  const int n = int(std::max<uint32_t>(line_bytes / cell_bytes, 1));
  const int log2n = __builtin_ctz(unsigned(n));
  w = 1 << ((log2n + 1) / 2);
  h = n / w;
}

// Texel block that one cache line of RGBA8 data holds (e.g. 128 B -> 8x4):
// the block of pixels or uncompressed texels the trace names by one line.
inline void line_block_shape(uint32_t line_bytes, int& block_w, int& block_h) { cells_per_line(line_bytes, 4, block_w, block_h); }

// Texels per line of texture `t` stored in `format`.
inline void texture_line_shape(const Texture& t, TextureFormat format, uint32_t line_bytes, int& block_w, int& block_h) {
  uint32_t cell = 4;  // RGBA8 texel
  int texels = 1;     // per cell side
  if (format != TextureFormat::rgba8 && t.compress) {
    const bool bc3 = format == TextureFormat::bc3 || (format == TextureFormat::bc && !t.opaque);
    cell = bc3 ? 16 : 8;
    texels = 4;
  }
  cells_per_line(line_bytes, cell, block_w, block_h);
  block_w *= texels;
  block_h *= texels;
}

struct TextureLayout {
  std::vector<uint32_t> first_line;  // per level drawn (level 0 only when not mip-mapped)
  std::vector<int> blocks_x;         // per level
  uint64_t lines = 0;                // total
};

inline TextureLayout texture_layout(const Texture& t, int block_w, int block_h) {
  TextureLayout l;
  const size_t levels = t.mipmapped ? t.levels.size() : std::min<size_t>(1, t.levels.size());
  uint64_t line = 0;
  for (size_t i = 0; i < levels; ++i) {
    const int bx = (t.levels[i].width + block_w - 1) / block_w, by = (t.levels[i].height + block_h - 1) / block_h;
    l.first_line.push_back(uint32_t(line));
    l.blocks_x.push_back(bx);
    line += uint64_t(bx) * uint64_t(by);
  }
  l.lines = line;
  return l;
}

}  // namespace oovr
