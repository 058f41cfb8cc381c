// oovr against a real GPU (docs/validation.md, "Hardware"): frame times
// measured through OpenGL on real hardware (by `oovr-reference --time`, or
// the H100 data shipped in docs/data/hardware/), set beside the frame times
// a scheme (single-gpm: one GPU) simulates for the same scenes, frames and
// resolutions. The GPU is not the paper's GPM, so what is compared is shape:
// the Pearson correlation of the medians per (scene, resolution), and how
// much the ratio oovr / GPU varies from point to point.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "oovr/core/config.h"

namespace oovr {

// One measured frame: a row of the CSV (times in microseconds).
struct HardwareFrame {
  std::string scene, resolution;  // resolution: the whole stereo frame, WxH
  int frame = 0;
  double full_us = 0;  // the stereo frame: every draw, both eyes
  double geom_us = 0;  // the same with a 1x1 scissor per eye (per-draw and vertex cost)
  double left_us = 0;  // the left eye only
  uint64_t draws = 0, triangles = 0;
};

// What the GPU drew, as the data say (docs/data/hardware/README.md): the
// frames are only comparable with oovr simulating this same workload.
struct HardwareWorkload {
  std::string commit;          // oovr's commit whose loaders built the scenes ("unknown" when not built from git)
  std::string materials;       // "real" or "one-pass": how the rows' scenes were drawn (their names say it too)
  std::string texture_format;  // how the GPU stored textures (oovr-reference uploads RGBA8: "rgba8")
  int aniso = 0;               // anisotropic filtering taps, trilinear below them
};

struct HardwareData {
  std::string renderer;  // GL_RENDERER of the machine measured
  HardwareWorkload workload;
  std::vector<HardwareFrame> frames;

  // Reads a CSV: lines "key,value" naming the renderer and the workload
  // (renderer, commit, materials, texture_format, aniso; each once, all but
  // renderer required), then a header naming (at least) scene, resolution,
  // frame, full_us, geom_us, left_us, draws, triangles, then one row per
  // frame; `scene` is the name oovr loads the drawn scene by, options
  // included. Throws Error naming the file, the line and the problem.
  static HardwareData read(const std::string& path);
  static HardwareData parse(const std::string& text, const std::string& name);
  // The CSV text of these frames (the format read() reads).
  std::string csv() const;
};

// One (scene, resolution) of the data, with oovr's frame times beside the
// GPU's, frame by frame, and the medians.
struct CorrelationPoint {
  std::string scene, resolution;
  std::vector<int> frames;
  std::vector<double> gpu_us, oovr_us;
  double gpu_median_us = 0, oovr_median_us = 0;
  double ratio() const { return oovr_median_us / gpu_median_us; }
};

struct Correlation {
  std::string scheme;
  HardwareWorkload workload;  // what the GPU drew, and so what oovr simulated
  std::vector<CorrelationPoint> points;
  double r = 0;                            // Pearson r of the medians, over the points
  double spread = 0;                       // largest ratio oovr / GPU over the smallest, of the medians
  double log_sd = 0;                       // standard deviation of log(oovr / GPU) over the medians: 0 when proportional
  std::map<std::string, double> r_within;  // per scene: Pearson r over its frames (all resolutions)
  std::vector<std::string> notes;          // differences between the data and oovr's scenes
};

struct CorrelationOptions {
  std::string scheme = "single-gpm";
  Config config;  // the machine (preset and --set)
  bool use_cache = true;
  std::function<void(const std::string&)> progress;
};

// Simulates every frame of `data` with the scheme (each frame after a
// warm-up run of itself, as the GPU's median of repetitions after one
// warm-up) on the workload the GPU drew: the scenes as the rows name them,
// textures stored as the data say (pipeline.texture_format, unless the
// configuration sets it) and the data's anisotropy; then correlates.
// Throws Error for an unknown scene or scheme, a scene whose draws or
// triangles differ from those measured (the workload changed since), a
// scheme with frames in flight, or data with fewer than two points.
Correlation correlate(const HardwareData& data, const CorrelationOptions& options);

// How general one calibrated value is (docs/validation.md): for each scene,
// the value of the sweep that makes oovr most nearly proportional to the GPU
// on the other scenes' points, and how far the scene left out then is from
// them: its median ratio oovr/GPU over the geometric mean ratio of the
// others (1 when the fit carries over exactly).
struct LeftOut {
  std::string scene;
  std::string value;    // fitted on the other scenes
  double held_out = 0;  // the scene's geometric mean ratio over the others'
  double r = 0;         // Pearson r of the medians over all points at that value
  double spread = 0;    // ratio spread over all points at that value
};
// `runs[i]` is the correlation at `values[i]` (of one key). Needs two scenes.
std::vector<LeftOut> leave_one_scene_out(const std::vector<std::string>& values, const std::vector<Correlation>& runs);

// The median of a series (NaN when empty).
double median(std::vector<double> v);
// Pearson's r of two series of equal length (0 when either is constant).
double pearson(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace oovr
