#include "oovr/memory/address_map.h"

#include <algorithm>

#include "oovr/core/error.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/tiled_layout.h"

namespace oovr {

AddressMap::AddressMap(Bytes page, Bytes line) : m_page(page.value), m_line(line.value) {
  if (m_line == 0 || m_page < m_line || m_page % m_line != 0) throw Error("address map: bad page or line size");
}

uint32_t AddressMap::add(std::string name, Category category, uint64_t bytes) {
  bytes = std::max(bytes, m_line);
  const uint64_t pages = (bytes + m_page - 1) / m_page;
  if (m_page_region.size() + pages > (uint64_t(1) << 32))
    throw Error("address map: more than 2^32 pages (region '" + name + "')");
  Region r{std::move(name), category, end(), bytes};
  const uint32_t id = uint32_t(m_regions.size());
  m_regions.push_back(std::move(r));
  m_page_region.insert(m_page_region.end(), pages, id);
  return id;
}

SceneLayout::SceneLayout(AddressMap& map, const Scene& scene, const FrameTrace& frame) : m_map(&map) {
  if (frame.line_bytes != map.line_bytes())
    throw Error("the FrameTrace was recorded with " + std::to_string(frame.line_bytes) + "-byte lines but memory.line is " +
                std::to_string(map.line_bytes()) + " bytes; render the trace again with the memory system's line size");
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    m_vertex.push_back(map.add("mesh" + std::to_string(m) + ".vertices", Category::vertex, mesh.vertex_bytes()));
    m_index.push_back(map.add("mesh" + std::to_string(m) + ".indices", Category::index, mesh.indices.size() * sizeof(uint32_t)));
  }
  for (size_t t = 0; t < scene.textures.size(); ++t) {
    int bw = 0, bh = 0;
    texture_line_shape(scene.textures[t], frame.texture_format, frame.line_bytes, bw, bh);
    const TextureLayout l = texture_layout(scene.textures[t], bw, bh);
    m_texture.push_back(
        map.add("texture" + std::to_string(t) + " " + scene.textures[t].name, Category::texture, l.lines * map.line_bytes()));
    m_texture_base.push_back(map.region(m_texture.back()).base);
  }
  m_line_bytes = map.line_bytes();
  const uint64_t tile_bytes = uint64_t(kTileSize) * kTileSize * 4;
  m_lines_per_tile = int(tile_bytes / map.line_bytes());
  // Blocks of one page of tiles, as square as a power of two allows.
  const int tiles_per_page = int(std::max<uint64_t>(1, map.page_bytes() / tile_bytes));
  const int log2 = __builtin_ctz(unsigned(tiles_per_page));
  m_block_w = 1 << ((log2 + 1) / 2);
  m_block_h = tiles_per_page / m_block_w;
  m_blocks_x = (frame.tiles_x + m_block_w - 1) / m_block_w;
  const int blocks_y = (frame.tiles_y + m_block_h - 1) / m_block_h;
  m_frame_bytes = uint64_t(m_blocks_x) * uint64_t(blocks_y) * uint64_t(tiles_per_page) * tile_bytes;
  m_colour = map.add("frame.colour", Category::colour, m_frame_bytes);
  m_depth = map.add("frame.depth", Category::depth, m_frame_bytes);
}

}  // namespace oovr
