// A FrameTrace as bytes: the payload of a trace-cache entry (trace_cache.h)
// and the entry around it, and what makes a trace one the renderer could
// have made. Read back as untrusted input: a payload or entry that is not
// whole and consistent is refused, never trusted (docs/reliability.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "oovr/pipeline/frame_trace.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr {

// The entry format; part of every cache key. Bump when the trace's meaning
// or layout changes (3: key and checksum).
constexpr uint32_t kTraceFormat = 3;

// The binary form of a trace (the payload of a cache entry; also used by the
// tests and the fuzz target). deserialize_trace accepts only a payload that
// is whole and internally consistent: every tile record names an object,
// eye and tile of the frame and a range of its texture lines, in the order
// the renderer writes them.
std::string serialize_trace(const FrameTrace& t);
std::optional<FrameTrace> deserialize_trace(std::string_view bytes);

// A cache entry: magic, format, the key, the payload's size and checksum,
// the payload. decode_entry returns the trace, or nothing with `why` set.
std::string encode_entry(const std::string& key, const FrameTrace& t);
std::optional<FrameTrace> decode_entry(std::string_view bytes, const std::string& key, std::string* why);

// What makes `t` a trace the renderer could not have made of `frame` of
// `scene` through `view` with `settings`: its frame, size, tiles, line and
// storage format, object count, and every texture line within its texture's
// layout. Empty when it could have.
std::string trace_mismatch(const FrameTrace& t, const Scene& scene, int frame, const StereoView& view,
                           const PipelineSettings& settings);

}  // namespace oovr
