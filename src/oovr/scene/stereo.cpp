#include "oovr/scene/stereo.h"

#include <charconv>

#include "oovr/core/error.h"

namespace oovr {

EyeCamera eye_camera(const CameraPath& path, int frame, const StereoRig& rig, int eye) {
  if (frame < 0 || frame >= int(path.frames.size()))
    throw Error("frame " + std::to_string(frame) + " is out of range: the camera path has " + std::to_string(path.frames.size()) +
                " frames (0 to " + std::to_string(int(path.frames.size()) - 1) + ")");
  const CameraPose& pose = path.frames[size_t(frame)];
  const Vec3 forward = normalize(pose.target - pose.position);
  const Vec3 right = normalize(cross(forward, pose.up));
  EyeCamera c;
  c.clip_from_eye =
      perspective(radians(path.fov_y_degrees), float(rig.eye_width) / float(rig.eye_height), path.z_near, path.z_far);
  c.offset_m = (eye == kLeft ? -0.5f : 0.5f) * rig.ipd_m;
  c.position = pose.position + right * c.offset_m;
  c.eye_from_world = look_at(c.position, c.position + forward, pose.up);
  return c;
}

StereoView make_stereo_view(const CameraPath& path, int frame, const StereoRig& rig) {
  StereoView v;
  v.frame_width = rig.frame_width();
  v.frame_height = rig.frame_height();
  for (int e = 0; e < kEyes; ++e) {
    const EyeCamera c = eye_camera(path, frame, rig, e);
    v.eye_position[e] = c.position;
    v.eye_offset_m[e] = c.offset_m;
    v.clip_from_world[e] = c.clip_from_eye * c.eye_from_world;
    v.viewport[e] = {e * rig.eye_width, 0, rig.eye_width, rig.eye_height};
  }
  return v;
}

static bool parse_wh(const std::string& text, int& w, int& h) {
  const auto x = text.find('x');
  if (x == std::string::npos) return false;
  const char* b = text.data();
  const char* e = b + text.size();
  auto r1 = std::from_chars(b, b + x, w);
  auto r2 = std::from_chars(b + x + 1, e, h);
  return r1.ec == std::errc() && r1.ptr == b + x && r2.ec == std::errc() && r2.ptr == e;
}

constexpr int kMaxSide = 16384;

StereoRig parse_frame_resolution(const std::string& text) {
  int w = 0, h = 0;
  if (!parse_wh(text, w, h) || w < 2 || h < 1 || w > kMaxSide || h > kMaxSide)
    throw Error("bad resolution '" + text + "': expected WxH with W from 2 to 16384 and H from 1 to 16384 (e.g. 1280x1024)");
  if (w % 2 != 0) throw Error("bad resolution '" + text + "': the width covers both eyes side by side and must be even");
  StereoRig rig;
  rig.eye_width = w / 2;
  rig.eye_height = h;
  return rig;
}

StereoRig parse_eye_resolution(const std::string& text) {
  int w = 0, h = 0;
  if (!parse_wh(text, w, h) || w < 1 || h < 1 || w > kMaxSide / 2 || h > kMaxSide)
    throw Error("bad per-eye resolution '" + text +
                "': expected WxH with W from 1 to 8192 and H from 1 to 16384 (e.g. 640x1024)");
  StereoRig rig;
  rig.eye_width = w;
  rig.eye_height = h;
  return rig;
}

}  // namespace oovr
