// FrameTrace: what the functional pipeline did for one stereo frame, recorded
// so that every parallel-rendering scheme can replay the same work through
// its own distribution, memory system and timing model without rendering
// again (DESIGN.md, "render once, replay per scheme").
//
// Granularity is (object, eye, screen tile): a scheme that sends an object to
// a GPM, an eye to a group of GPMs or a tile to its owner finds the work of
// that piece here. Geometry work is per object (SMP: transformed once for
// both eyes); triangles set up are per (object, eye).
//
// Addresses are not absolute: texture lines are (texture, line index in the
// texture's tiled layout) and framebuffer lines are bits of a mask within one
// tile. The memory system gives them homes and addresses.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "oovr/core/uninitialised.h"
#include "oovr/pipeline/tiled_layout.h"

namespace oovr {

// Texture line: texture index in the high 32 bits, line index in the low 32.
// The line's byte offset in the texture is line_index * line_bytes; lines of
// level n follow those of level n-1; within a level, a line holds a
// block_w x block_h block of texels and blocks are in row-major order.
using TexLine = uint64_t;
constexpr TexLine make_tex_line(uint32_t texture, uint32_t line) { return (uint64_t(texture) << 32) | line; }
constexpr uint32_t tex_line_texture(TexLine l) { return uint32_t(l >> 32); }
constexpr uint32_t tex_line_index(TexLine l) { return uint32_t(l); }

// Work of one object for one eye in one 16x16 screen tile.
struct TileWork {
  uint32_t object = 0;
  uint16_t eye = 0;
  uint16_t tile_x = 0, tile_y = 0;  // tile coordinates; y counts up from the frame's bottom row
  // Explicit and zero (with reserved1), so that every byte of a record is
  // set: the trace cache stores records as bytes under a checksum, and a
  // trace must have one byte form (trace_cache.cpp asserts there is no
  // hidden padding).
  uint16_t reserved0 = 0;
  uint32_t triangles = 0;  // triangles binned to this tile (after clip and cull)
  uint32_t vertices = 0;   // distinct mesh vertices of those triangles
  uint32_t quads = 0;      // 2x2 quads shaded (at least one fragment shaded)
  uint32_t covered = 0;    // fragments inside the triangles and the eye's viewport
  // Fragments shaded: with an early depth test (passes without alpha test)
  // only those that passed it; otherwise every covered fragment.
  uint32_t shaded = 0;
  uint32_t passed = 0;   // fragments that passed the alpha and depth tests
  uint32_t samples = 0;  // bilinear texture lookups (trilinear = 2, anisotropic = 2 per probe)
  // Framebuffer lines of this tile (bit i = line i of the tile's colour or
  // depth block): depth lines read by the depth test; colour lines read by
  // blending (passes whose result depends on the frame); colour lines
  // written by passed fragments, depth lines by those of passes that write
  // depth.
  uint32_t depth_read_mask = 0;
  uint32_t depth_write_mask = 0;
  uint32_t colour_read_mask = 0;
  uint32_t colour_write_mask = 0;
  // Range in FrameTrace::tex_lines: the texture lines sampled, in shading
  // order; repeats within one 2x2 quad are merged (a texture unit coalesces
  // the requests of a quad), repeats across quads are kept.
  uint64_t tex_begin = 0;
  uint32_t tex_count = 0;
  uint32_t reserved1 = 0;

  bool operator==(const TileWork&) const = default;
};

// Geometry work of one object (SMP: vertices are transformed once and
// projected into both eyes).
struct ObjectWork {
  uint32_t vertices = 0;         // vertices transformed
  uint32_t triangles = 0;        // triangles assembled
  uint32_t setup[2] = {0, 0};    // triangles set up per eye (after clip and cull)
  uint32_t culled[2] = {0, 0};   // triangles dropped per eye: back-facing, empty, or outside the view
  uint32_t clipped[2] = {0, 0};  // triangles that needed clipping per eye
  uint64_t vertex_bytes = 0;     // bytes of the vertex buffer
  uint64_t index_bytes = 0;      // bytes of the index buffer
  // Scalar instructions a fragment lane runs for this draw's pass
  // (pipeline/shader_cost.h).
  uint32_t fragment_instructions = 0;
  uint32_t texture_layers = 0;  // texture layers the pass samples

  bool operator==(const ObjectWork&) const = default;
};

// A frame's texture lines less the repeats within each record, modulo a
// power of two: line i of a record is a repeat, modulo M, when the record's
// last line before it with the same index modulo M is the same line. Where
// a cache of M sets indexes a texture's lines by their index (its base a
// multiple of M lines), that read is of its set's most recently used line,
// a hit that changes nothing whatever the cache held (schemes/frame_sim.cpp).
// For a cache that replaces the least recently used of W ways, also the
// reads sure to hit whose line the record reads again before anything of
// the set may miss (frame_trace.cpp says why that changes nothing either).
struct TexLinesWithoutRepeats {
  uint64_t modulus = 0;
  int lru_ways = 0;             // W; 0: the repeats of any policy only
  std::vector<TexLine> lines;   // every record's lines that are not repeats, record after record
  std::vector<uint64_t> begin;  // record r's are lines[begin[r] .. begin[r + 1]); one entry per record and one more
};

// What FrameTrace derives from itself once and shares between the threads
// and runs that replay it. A copied or moved-to trace derives anew.
class FrameTraceMemo {
 public:
  FrameTraceMemo();
  FrameTraceMemo(const FrameTraceMemo&);
  FrameTraceMemo& operator=(const FrameTraceMemo&);
  ~FrameTraceMemo();

 private:
  friend struct FrameTrace;
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

struct FrameTrace {
  int frame = 0;
  int frame_width = 0, frame_height = 0;
  int tile_size = 16;
  int tiles_x = 0, tiles_y = 0;
  uint32_t line_bytes = 128;
  int block_w = 8, block_h = 4;  // framebuffer pixels per line (RGBA8 colour, 32-bit depth)
  // How textures are stored: the texels a texture line holds
  // (texture_line_shape in pipeline/tiled_layout.h).
  TextureFormat texture_format = TextureFormat::rgba8;
  std::vector<ObjectWork> objects;  // indexed by object
  // Sorted by (object, eye, tile_y, tile_x): draw order, then eye, then tile.
  std::vector<TileWork> tiles;
  UninitialisedVector<TexLine> tex_lines;

  uint64_t total_covered() const;
  uint64_t total_passed() const;
  // Texture layers sampled over the frame: each shaded fragment times the
  // layers its pass samples ("texture fetches", whatever their filtering).
  uint64_t layer_fetches() const;
  // Distinct texture lines the frame touched (x line_bytes: the texture
  // bytes it needed, in the storage format).
  uint64_t unique_tex_lines() const;
  // The texture lines less their repeats modulo `modulus` (a power of two,
  // at most 2^20) and, with `lru_ways`, in an LRU cache of that many ways
  // (1 to 1024, modulus x (ways + 1) at most 2^24: the scratch is bounded);
  // computed on first use and kept; null when at least half the lines would
  // stay, where replaying the list is no shorter than the whole. Computed
  // from the trace as it is then: a trace is not changed once it is
  // replayed (a changed size or storage is derived anew).
  std::shared_ptr<const TexLinesWithoutRepeats> tex_lines_without_repeats(uint64_t modulus, int lru_ways = 0) const;
  // Whether tex_lines_without_repeats takes this modulus and these ways (it
  // throws Error otherwise).
  static bool repeats_derivable(uint64_t modulus, int lru_ways);
  // checksum64 of the records' bytes, computed on first use and kept (as
  // the list above: for the records as they are then).
  uint64_t records_checksum() const;

  mutable FrameTraceMemo memo;
};

}  // namespace oovr
