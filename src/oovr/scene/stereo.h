// The stereo rig: two eyes side by side in one frame, as in the paper's SMP
// engine (Section 2.1): the frame's width covers both eyes, the left eye's
// viewport is the left half and the right eye's the right half.
#pragma once

#include <string>

#include "oovr/core/math.h"
#include "oovr/scene/scene.h"

namespace oovr {

enum Eye : int { kLeft = 0, kRight = 1 };
constexpr int kEyes = 2;

struct Viewport {
  int x = 0, y = 0, width = 0, height = 0;
};

struct StereoRig {
  float ipd_m = 0.064f;  // interpupillary distance, metres (default 64 mm)
  int eye_width = 640;   // pixels per eye
  int eye_height = 1024;
  int frame_width() const { return 2 * eye_width; }
  int frame_height() const { return eye_height; }
};

// Everything the pipeline needs to draw one stereo frame.
struct StereoView {
  int frame_width = 0, frame_height = 0;
  // 2 for stereo; 1 renders only viewport[0] (a mono view, used to check that
  // SMP stereo equals two mono renders).
  int eyes = kEyes;
  Viewport viewport[kEyes];
  Mat4 clip_from_world[kEyes];  // projection * view, per eye
  Vec3 eye_position[kEyes];
  // Each eye's offset from the head along the head's right axis, metres
  // (-ipd/2 and +ipd/2; 0 in a mono view): how captured 3-D draws are
  // re-projected (DrawView::captured).
  float eye_offset_m[kEyes] = {0, 0};
};

// The view of frame `frame` of the scene's camera path. Each eye is the head
// pose shifted by -/+ ipd/2 along the head's right axis, both looking along
// the head's forward direction (parallel axes, symmetric frusta).
StereoView make_stereo_view(const CameraPath& path, int frame, const StereoRig& rig);

// One eye's camera of frame `frame`, the two matrices make_stereo_view
// composes: what a game loads as its projection and (times each object's
// placement) its modelview. Throws Error when the frame is out of range.
struct EyeCamera {
  Mat4 clip_from_eye, eye_from_world;
  Vec3 position;
  float offset_m = 0;  // along the head's right axis
};
EyeCamera eye_camera(const CameraPath& path, int frame, const StereoRig& rig, int eye);

// Parses "WxH" (the whole side-by-side stereo frame; W must be even) into a
// rig. Throws Error naming the bad value.
StereoRig parse_frame_resolution(const std::string& text);
// Parses "WxH" for one eye.
StereoRig parse_eye_resolution(const std::string& text);

}  // namespace oovr
