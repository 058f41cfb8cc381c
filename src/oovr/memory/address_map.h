// One address space for everything a frame touches (DESIGN.md): vertex and
// index buffers, textures in their tiled layout, framebuffers. Regions are
// page-aligned, so a page belongs to exactly one region.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "oovr/core/units.h"
#include "oovr/memory/category.h"
#include "oovr/pipeline/frame_trace.h"
#include "oovr/scene/scene.h"

namespace oovr {

struct Region {
  std::string name;
  Category category = Category::command;
  uint64_t base = 0;   // bytes, page-aligned
  uint64_t bytes = 0;  // size used (the last page may be partly empty)
};

class AddressMap {
 public:
  AddressMap(Bytes page, Bytes line);
  // Adds a region of `bytes` (at least one line) and returns its id.
  uint32_t add(std::string name, Category category, uint64_t bytes);
  const Region& region(uint32_t id) const { return m_regions[id]; }
  size_t regions() const { return m_regions.size(); }
  // The region holding a page (pages are allocated densely from 0).
  uint32_t region_of_page(uint64_t page) const { return m_page_region[size_t(page)]; }
  uint64_t pages() const { return m_page_region.size(); }
  // Bytes of a page its region uses (a region's last page may be partly
  // empty; a small buffer uses a small part of its only page).
  uint64_t page_used_bytes(uint64_t page) const {
    const Region& r = m_regions[m_page_region[size_t(page)]];
    const uint64_t start = page * m_page, end = r.base + r.bytes;
    return end <= start ? 0 : std::min<uint64_t>(m_page, end - start);
  }
  uint64_t page_bytes() const { return m_page; }
  uint64_t line_bytes() const { return m_line; }
  uint64_t end() const { return m_page_region.size() * m_page; }

 private:
  uint64_t m_page, m_line;
  std::vector<Region> m_regions;
  std::vector<uint32_t> m_page_region;
};

// Where a scene's resources and a stereo frame's buffers live: a region per
// mesh vertex buffer, mesh index buffer and texture (every mip level in the
// FrameTrace's tiled layout), plus the frame's colour and depth buffers.
// Framebuffers are block-linear, as GPUs lay them out: each 16x16 screen
// tile (1 KB) is contiguous, and the tiles of one page form a block of
// block_w x block_h tiles (8x8 tiles, 128x128 pixels, for 64 KB pages);
// blocks are row-major from the bottom of the frame, tiles row-major within.
class SceneLayout {
 public:
  SceneLayout(AddressMap& map, const Scene& scene, const FrameTrace& frame);

  uint32_t vertex_region(int mesh) const { return m_vertex[size_t(mesh)]; }
  uint32_t index_region(int mesh) const { return m_index[size_t(mesh)]; }
  uint32_t texture_region(int texture) const { return m_texture[size_t(texture)]; }
  uint32_t colour_region() const { return m_colour; }
  uint32_t depth_region() const { return m_depth; }

  // Address of a texture line recorded in a FrameTrace (every texture line
  // of every replay comes here: the bases are kept beside the region ids).
  uint64_t texture_line(TexLine l) const {
    return m_texture_base[tex_line_texture(l)] + uint64_t(tex_line_index(l)) * m_line_bytes;
  }
  // Address of a tile of a framebuffer: its line 0 (the tile's lines are
  // contiguous, one every line's bytes).
  uint64_t tile_address(uint32_t region, int tile_x, int tile_y) const {
    return m_map->region(region).base + tile_slot(tile_x, tile_y) * uint64_t(m_lines_per_tile) * m_line_bytes;
  }
  // Address of line `line` (0 .. lines_per_tile-1) of a tile of a framebuffer.
  uint64_t frame_line(uint32_t region, int tile_x, int tile_y, int line) const {
    return tile_address(region, tile_x, tile_y) + uint64_t(line) * m_line_bytes;
  }
  int lines_per_tile() const { return m_lines_per_tile; }
  // Which page-sized block of tiles a tile belongs to, and how big blocks are.
  int block_of(int tile_x, int tile_y) const { return (tile_y / m_block_h) * m_blocks_x + tile_x / m_block_w; }
  int block_w() const { return m_block_w; }
  int block_h() const { return m_block_h; }
  // Bytes of one framebuffer (colour or depth) in this layout.
  uint64_t frame_bytes() const { return m_frame_bytes; }

 private:
  const AddressMap* m_map;
  std::vector<uint32_t> m_vertex, m_index, m_texture;
  std::vector<uint64_t> m_texture_base;  // per texture, its region's base
  uint64_t m_line_bytes = 0;
  uint32_t m_colour = 0, m_depth = 0;
  uint64_t tile_slot(int tx, int ty) const {
    return uint64_t(block_of(tx, ty)) * uint64_t(m_block_w * m_block_h) + uint64_t((ty % m_block_h) * m_block_w + tx % m_block_w);
  }
  int m_lines_per_tile = 0;
  int m_block_w = 1, m_block_h = 1, m_blocks_x = 1;
  uint64_t m_frame_bytes = 0;
};

}  // namespace oovr
