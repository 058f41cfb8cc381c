#include "oovr/pipeline/trace_format.h"

#include <array>
#include <cstring>
#include <type_traits>

#include "oovr/core/bytes.h"
#include "oovr/core/hash.h"
#include "oovr/pipeline/tiled_layout.h"

namespace oovr {

namespace {

constexpr char kMagic[8] = {'O', 'O', 'V', 'R', 'T', 'R', 'C', '1'};

uint64_t checksum(std::string_view b) { return checksum64(b); }

// Records are written as their bytes, so they must have no padding whose
// bytes nobody set (a checksum would see noise).
static_assert(std::has_unique_object_representations_v<TileWork>);
static_assert(std::has_unique_object_representations_v<ObjectWork>);
static_assert(std::has_unique_object_representations_v<TexLine>);

}  // namespace

std::string serialize_trace(const FrameTrace& t) {
  std::string out;
  out.reserve(64 + t.objects.size() * sizeof(ObjectWork) + t.tiles.size() * sizeof(TileWork) +
              t.tex_lines.size() * sizeof(TexLine));
  put(out, t.frame);
  put(out, t.frame_width);
  put(out, t.frame_height);
  put(out, t.tile_size);
  put(out, t.tiles_x);
  put(out, t.tiles_y);
  put(out, t.line_bytes);
  put(out, t.block_w);
  put(out, t.block_h);
  put(out, t.texture_format);
  put_vector(out, t.objects);
  put_vector(out, t.tiles);
  put_vector(out, t.tex_lines);
  return out;
}

std::optional<FrameTrace> deserialize_trace(std::string_view bytes) {
  ByteReader r(bytes);
  FrameTrace t;
  if (!(r.get(t.frame) && r.get(t.frame_width) && r.get(t.frame_height) && r.get(t.tile_size) && r.get(t.tiles_x) &&
        r.get(t.tiles_y) && r.get(t.line_bytes) && r.get(t.block_w) && r.get(t.block_h) && r.get(t.texture_format)))
    return std::nullopt;
  // The header first, so that nothing below divides by or indexes with a
  // value the renderer could not have written.
  constexpr int kMaxSide = 1 << 16;
  if (t.frame < 0 || t.frame_width <= 0 || t.frame_height <= 0 || t.frame_width > kMaxSide || t.frame_height > kMaxSide ||
      t.tile_size != kTileSize || t.tiles_x != (t.frame_width + kTileSize - 1) / kTileSize ||
      t.tiles_y != (t.frame_height + kTileSize - 1) / kTileSize || t.line_bytes < 32 || t.line_bytes > 1024 ||
      (t.line_bytes & (t.line_bytes - 1)) != 0 || uint8_t(t.texture_format) > uint8_t(TextureFormat::bc))
    return std::nullopt;
  int bw = 0, bh = 0;
  line_block_shape(t.line_bytes, bw, bh);
  if (t.block_w != bw || t.block_h != bh) return std::nullopt;
  if (!(r.get_vector(t.objects) && r.get_vector(t.tiles) && r.get_vector(t.tex_lines) && r.done())) return std::nullopt;
  // Tile records in the renderer's order, (object, eye, tile_y, tile_x),
  // each once, each naming a tile of the frame and a range of its lines.
  const auto order = [](const TileWork& w) { return std::array<uint64_t, 4>{w.object, w.eye, w.tile_y, w.tile_x}; };
  for (size_t i = 0; i < t.tiles.size(); ++i) {
    const TileWork& w = t.tiles[i];
    if (w.object >= t.objects.size() || w.eye >= kEyes || w.tile_x >= t.tiles_x || w.tile_y >= t.tiles_y ||
        w.tex_begin > t.tex_lines.size() || w.tex_count > t.tex_lines.size() - w.tex_begin)
      return std::nullopt;
    if (i > 0 && !(order(t.tiles[i - 1]) < order(w))) return std::nullopt;
  }
  return t;
}

std::string encode_entry(const std::string& key, const FrameTrace& t) {
  const std::string payload = serialize_trace(t);
  std::string out(kMagic, sizeof kMagic);
  put(out, kTraceFormat);
  put(out, uint32_t(key.size()));
  out += key;
  put(out, uint64_t(payload.size()));
  put(out, checksum(payload));
  out += payload;
  return out;
}

std::optional<FrameTrace> decode_entry(std::string_view bytes, const std::string& key, std::string* why) {
  const auto fail = [&](const std::string& w) -> std::optional<FrameTrace> {
    if (why) *why = w;
    return std::nullopt;
  };
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    return fail("not a trace-cache entry (bad magic)");
  ByteReader r(bytes.substr(sizeof kMagic));
  uint32_t format = 0, key_size = 0;
  if (!r.get(format)) return fail("truncated header");
  if (format != kTraceFormat) return fail("format " + std::to_string(format) + ", expected " + std::to_string(kTraceFormat));
  std::string_view stored_key;
  if (!r.get(key_size) || !r.get_bytes(key_size, stored_key)) return fail("truncated header");
  if (stored_key != key) return fail("stored under another key");
  uint64_t size = 0, sum = 0;
  if (!r.get(size) || !r.get(sum)) return fail("truncated header");
  if (size != r.left()) return fail("payload of " + std::to_string(r.left()) + " bytes, the header says " + std::to_string(size));
  const std::string_view payload = bytes.substr(bytes.size() - size);
  if (checksum(payload) != sum) return fail("checksum mismatch");
  auto t = deserialize_trace(payload);
  if (!t) return fail("inconsistent trace");
  return t;
}

std::string trace_mismatch(const FrameTrace& t, const Scene& scene, int frame, const StereoView& view,
                           const PipelineSettings& settings) {
  if (t.frame != frame) return "a trace of frame " + std::to_string(t.frame) + ", not " + std::to_string(frame);
  if (t.frame_width != view.frame_width || t.frame_height != view.frame_height)
    return "a trace of a " + std::to_string(t.frame_width) + "x" + std::to_string(t.frame_height) + " frame";
  if (t.line_bytes != settings.line_bytes || t.texture_format != settings.texture_format)
    return "a trace with another line size or texture format";
  if (t.objects.size() != scene.draws(frame).size())
    return "a trace of " + std::to_string(t.objects.size()) + " objects, the scene's frame has " +
           std::to_string(scene.draws(frame).size());
  for (const TileWork& w : t.tiles)
    if (w.eye >= view.eyes) return "a trace with more eyes than the view";
  if (!settings.record_texture_lines && !t.tex_lines.empty()) return "a trace with texture lines where none are recorded";
  // Lines per texture in its storage format (tiled_layout.h).
  std::vector<uint64_t> lines(scene.textures.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    int bw = 0, bh = 0;
    texture_line_shape(scene.textures[i], settings.texture_format, settings.line_bytes, bw, bh);
    lines[i] = texture_layout(scene.textures[i], bw, bh).lines;
  }
  for (const TexLine l : t.tex_lines) {
    const uint32_t tex = tex_line_texture(l);
    if (tex >= lines.size() || tex_line_index(l) >= lines[tex]) return "a texture line outside the scene's textures";
  }
  return {};
}

}  // namespace oovr
