// A captured game's frames, drawn by oovr, against the real driver's
// images of the same frames: glretrace (apitrace's replayer) on Mesa's
// llvmpipe writes a snapshot of every frame; oovr draws each frame of the
// scene mono, at the capture's window size, with the game's sampler
// settings, and compares (docs/validation.md, "Captured frames").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oovr/scene/scene.h"

namespace oovr {

struct CaptureFrameCheck {
  int frame = 0;       // of the scene
  int game_frame = 0;  // of the capture (its snapshot's number)
  // The game's draw calls and their triangles (as OpenGL splits them), and
  // the depth clears oovr draws besides (docs/real-frames.md).
  uint64_t draws = 0, triangles = 0, clears = 0;
  bool snapshot = false;  // a snapshot was there
  double psnr = 0;        // dB over RGB; infinite when identical
};

struct CaptureCheckOptions {
  std::string snapshots;   // folder of glretrace's NNNNNNNNNN.png (-s DIR/ --call-nos=false)
  int max_anisotropy = 1;  // ioquake3's default: no anisotropic filtering
  std::string diff_dir;    // when set: oovr's image of each frame, as PNG
};

// Checks every frame of `scene` (a captured game). Throws Error when the
// scene is not one or a snapshot cannot be read or has another size.
std::vector<CaptureFrameCheck> check_capture(const Scene& scene, const CaptureCheckOptions& o);

// The round trip (docs/validation.md): a capture of oovr-reference drawing
// a built-in scene through OpenGL 1.x (oovr-reference --fixed-function),
// imported, against that scene itself. Frame k of the capture's window is
// frame capture_first_frame + k of the scene (the reference draws from
// frame 0); both are drawn by oovr, mono, at the capture's window, the
// scene through its own camera with no eye offset.
struct RoundTripFrame {
  int frame = 0;
  // [0]: the imported capture, [1]: the scene.
  uint64_t draws[2] = {0, 0}, triangles[2] = {0, 0};
  uint64_t covered[2] = {0, 0}, passed[2] = {0, 0};  // fragments
  uint64_t fetches[2] = {0, 0};                      // texture layers sampled
  double psnr = 0;                                   // dB over RGB; infinite when identical
};

// Throws Error when `captured` is not a capture or its frames run past the
// scene's camera path.
std::vector<RoundTripFrame> check_round_trip(const Scene& captured, const Scene& original, int max_anisotropy = 1);

}  // namespace oovr
