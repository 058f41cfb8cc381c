// The tiled layout of a texture in memory: one cache line holds a
// block_w x block_h block of RGBA8 texels; a level's blocks are row-major;
// levels follow each other. The sampler records line indices in this layout
// and the memory system gives them addresses, so both use this one function.
#pragma once

#include <cstdint>
#include <vector>

#include "oovr/scene/texture.h"

namespace oovr {

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
