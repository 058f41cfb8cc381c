// libFuzzer target: the trace-cache reader. decode_entry must refuse
// anything but a whole entry under its key with a matching checksum;
// deserialize_trace (the payload behind the checksum, fuzzed directly
// because a fuzzer cannot forge checksums) must accept only traces every
// consumer can index safely: every tile record inside the frame, its
// object and its texture-line range in the trace. The same bytes are also
// read as a cached import (decode_scene, scene/scene_codec.h): a scene it
// accepts must validate and encode back to the same bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/pipeline/trace_cache.h"
#include "oovr/scene/scene_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::string why;
  (void)oovr::decode_entry(bytes, "0123456789abcdef", &why);
  if (const auto scene = oovr::decode_scene(bytes, &why)) {
    scene->validate();  // throws, uncaught, if decode_scene let a bad scene through
    if (oovr::encode_scene(*scene) != bytes) __builtin_trap();
  }
  const auto t = oovr::deserialize_trace(bytes);
  if (!t) return 0;
  uint64_t lines = 0;
  for (const oovr::TileWork& w : t->tiles) {
    if (w.object >= t->objects.size() || w.tile_x >= t->tiles_x || w.tile_y >= t->tiles_y || w.eye > 1) __builtin_trap();
    for (uint64_t i = w.tex_begin; i < w.tex_begin + w.tex_count; ++i) lines += t->tex_lines[i];  // in range
  }
  (void)t->unique_tex_lines();
  (void)t->layer_fetches();
  // What was read serialises back to the same bytes.
  if (oovr::serialize_trace(*t) != bytes) __builtin_trap();
  return int(lines & 0);
}
