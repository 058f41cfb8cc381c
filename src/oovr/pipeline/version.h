// The renderer's version, part of every trace-cache key (trace_cache.h).
//
// A FrameTrace is decided by the scene's content, the frame, the stereo view,
// the pipeline settings and the code that renders it. The first four are in
// the key as values; the code is this number. Bump it in the commit that
// changes what the renderer writes for some input (rasterisation, shading
// cost, texture addressing, the trace's fields), so that no cache replays
// the old output; leave it alone for changes elsewhere (a scheme, the timing
// model, the CLI), so that their rebuilds keep every cached trace.
//
// tests/test_pipeline_version.cpp holds the traces of a few reference frames
// by hash: a renderer change that forgets the bump fails it, naming the frame.
#pragma once

#include <cstdint>

namespace oovr {

// 2: fetch-only layers (Combine::fetch, a captured GLSL program's textures)
//    are sampled, not combined, and cost what the program computes with them.
// 3: an anisotropic footprint whose axes' ratio is past INT_MAX or infinite
//    takes the most probes (its conversion to int was undefined: one probe
//    on x86-64). No reference frame, and no frame of the paper's scenes at
//    its resolutions, has one; a cache may hold a trace of a frame that does.
inline constexpr uint32_t kPipelineVersion = 3;

}  // namespace oovr
