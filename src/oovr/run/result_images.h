// Pictures of a scheme's run over its first frame: which GPM shaded each
// pixel, and how many bytes each screen tile's work moved between GPMs
// (`oovr simulate --gpm-image / --traffic-image`, and the reports).
#pragma once

#include <string>

#include "oovr/pipeline/image.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

// GPM `gpm`'s colour in gpm_image, "#rrggbb" (for legends).
std::string gpm_colour(int gpm);

// The frame with each pixel coloured by the GPM that shaded it (the last
// writer's tile owner, r.owner), darkened by the frame's brightness so the
// scene stays readable; pixels no object covers are black.
Image gpm_image(const FrameOutput& out, const SchemeResult& r);

// Bytes moved between GPMs for each screen tile's work
// (r.tile_inter_gpm_bytes), black (none) through red to yellow (the most),
// on a square-root scale.
Image traffic_image(const FrameOutput& out, const SchemeResult& r);

}  // namespace oovr
