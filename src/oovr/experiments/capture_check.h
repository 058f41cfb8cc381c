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

}  // namespace oovr
