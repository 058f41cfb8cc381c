// oovr-reference: renders a scene with Mesa's llvmpipe and, with --compare,
// compares it with oovr's pipeline: image PSNR and per-draw fragment counts.
// With --time it measures GPU frame times (GL_TIME_ELAPSED) on whatever
// OpenGL the machine has (a GPU through EGL's device platform, else
// llvmpipe) and writes them in the format `oovr correlate` reads.
//
// With --fixed-function it draws the scene's frames as an OpenGL 1.x game
// does, for apitrace to capture (the round trip, tests/cli/roundtrip.sh).
//
// Exit status: 0 when the comparison passes (or nothing was compared), 1 when
// it fails its thresholds or something goes wrong, 2 for a bad argument, and
// 77 (reported by CTest as "skipped") when no OpenGL context can be made.
#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "fixed_function.h"
#include "gl_renderer.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"
#include "oovr/core/version.h"
#include "oovr/experiments/hardware.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/load.h"

namespace {

using namespace oovr;

struct Args {
  std::vector<std::string> scenes;
  std::string scene;
  int frame = 0;
  std::string resolution = "640x480";
  std::string out, oovr_out, diff_out;
  bool compare = false;
  double min_psnr = 35.0;
  double max_draw_diff_percent = 0.5;
  int isolate = -1;
  bool list = false;
  // --time
  bool time = false;
  int frames = 16;
  std::string resolutions;
  int repeat = 5;
  int aniso = 16;
  std::string csv;
  std::string platform = "gpu";
  bool fixed_function = false;
};

struct CountStats {
  uint64_t oovr = 0, gl = 0;
  int draws = 0, exact = 0, over = 0;
  double worst = 0;
  std::string worst_name;
  uint64_t worst_oovr = 0, worst_gl = 0;
};

void accumulate(CountStats& s, uint64_t a, uint64_t b, const std::string& name, double limit) {
  s.oovr += a;
  s.gl += b;
  if (a == 0 && b == 0) return;
  ++s.draws;
  if (a == b) ++s.exact;
  const uint64_t diff = a > b ? a - b : b - a;
  const double rel = double(diff) / double(std::max<uint64_t>(b, 1)) * 100.0;
  // One fragment is one pixel on an edge: on a draw of a few fragments it
  // is far more than 0.5%, yet it is the smallest possible disagreement
  // (docs/validation.md, accepted deviations), so it alone does not fail.
  if (rel > limit && diff > 1) ++s.over;
  if (rel > s.worst) {
    s.worst = rel;
    s.worst_name = name;
    s.worst_oovr = a;
    s.worst_gl = b;
  }
}

void print_counts(const char* what, const CountStats& s, double limit) {
  const double total = s.gl ? (double(s.oovr) - double(s.gl)) / double(s.gl) * 100.0 : 0.0;
  fmt::print("  {} fragments: oovr {} GL {} ({:+.4f}%); {} draws (object x eye), {} exact, {} over {}% and 1 fragment", what,
             s.oovr, s.gl, total, s.draws, s.exact, s.over, limit);
  if (s.worst > 0) fmt::print("; worst '{}' {:.3f}% ({} vs {})", s.worst_name, s.worst, s.worst_oovr, s.worst_gl);
  fmt::print("\n");
}

Image diff_image(const Image& a, const Image& b) {
  Image d(a.width, a.height);
  for (size_t i = 0; i < a.rgba.size(); i += 4) {
    int m = 0;
    for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])));
    const uint8_t v = uint8_t(std::min(255, m * 8));
    d.rgba[i] = v;
    d.rgba[i + 1] = v;
    d.rgba[i + 2] = v;
    d.rgba[i + 3] = 255;
  }
  return d;
}

// Exit 77 (skipped) when a game level's data is not installed.
bool data_missing(const std::string& scene) {
  const std::string why = scene_data_missing(scene);
  if (!why.empty()) fmt::print("SKIPPED: {}\n", why);
  return !why.empty();
}

// --time: frames --frame .. --frame + --frames - 1 of every scene at every
// resolution, as oovr correlate reads them (docs/validation.md).
// The reference draws scenes whose draws are the same in every frame; a
// captured game's frames are validated against glretrace, apitrace's own
// replayer of the capture (docs/validation.md).
Scene load_reference_scene(const std::string& name) {
  Scene s = load_scene(name);
  if (s.captured())
    throw Error("scene '" + name + "' is a captured game: the reference renderer does not draw it; " +
                "it is compared with glretrace's snapshots of the capture instead (docs/validation.md)");
  return s;
}

int time_frames(const Args& a) {
  std::vector<std::string> resolutions = split_list(a.resolutions);
  if (resolutions.empty()) resolutions.push_back(a.resolution);
  for (const auto& r : resolutions) (void)parse_frame_resolution(r);
  for (const auto& s : a.scenes)
    if (data_missing(s)) return 77;
  if (!a.csv.empty()) check_output_path(a.csv, "CSV output");
  std::unique_ptr<reference::GlRenderer> gl;
  try {
    gl = std::make_unique<reference::GlRenderer>(a.platform == "gpu" ? reference::Platform::any : reference::Platform::llvmpipe);
  } catch (const reference::Unavailable& e) {
    fmt::print("SKIPPED: no OpenGL 4.5 context: {}\n", e.what());
    return 77;
  }
  HardwareData data;
  data.renderer = gl->renderer_name();
  // What is drawn, as the data must say (oovr correlate simulates exactly
  // that): the scenes as named, their loaders at this commit, textures
  // uploaded as RGBA8 (GlRenderer), the anisotropy asked for.
  int one_pass = 0;
  for (const auto& s : a.scenes) one_pass += s.find("materials=one-pass") != std::string::npos;
  if (one_pass != 0 && one_pass != int(a.scenes.size()))
    throw Error("--scene: time the scenes all with their real materials or all as one-pass workloads (materials=one-pass)");
  data.workload = {git_commit(), one_pass ? "one-pass" : "real", "rgba8", a.aniso};
  fmt::print("timing on {}: {} repetitions after one warm-up, anisotropy {}\n", data.renderer, a.repeat, a.aniso);
  for (const auto& name : a.scenes) {
    const Scene scene = load_reference_scene(name);
    const int path = int(scene.camera.frames.size());
    if (a.frame >= path)
      throw Error("frame " + std::to_string(a.frame) + " is out of range: the camera path has " + std::to_string(path) +
                  " frames");
    for (const auto& res : resolutions) {
      const StereoRig rig = parse_frame_resolution(res);
      std::vector<StereoView> views;
      std::vector<int> frames;
      for (int k = 0; k < a.frames; ++k) {
        frames.push_back((a.frame + k) % path);
        views.push_back(make_stereo_view(scene.camera, frames.back(), rig));
      }
      const std::vector<reference::FrameTime> t = gl->time(scene, frames, views, a.aniso, a.repeat);
      double sum = 0;
      for (size_t k = 0; k < t.size(); ++k) {
        data.frames.push_back(
            {name, res, frames[k], t[k].full_us, t[k].geom_us, t[k].left_us, scene.objects.size(), scene.triangle_count()});
        sum += t[k].full_us;
      }
      fmt::print("  {} {}: {} frames, mean {:.1f} us per stereo frame\n", name, res, t.size(), sum / double(t.size()));
    }
  }
  if (a.csv.empty()) {
    fmt::print("{}", data.csv());
  } else {
    write_output_file(a.csv, data.csv(), "CSV output");
    fmt::print("wrote {} frames to {}\n", data.frames.size(), a.csv);
  }
  return 0;
}

int compare(const Args& a, const StereoRig& rig);

// --fixed-function: frames --frame .. --frame + --frames - 1, mono, in a
// window of --resolution.
int fixed_function(const Args& a) {
  if (a.scenes.size() != 1) throw Error("--scene: give exactly one scene with --fixed-function");
  if (data_missing(a.scenes.front())) return 77;
  const Scene scene = load_reference_scene(a.scenes.front());
  const StereoRig window = parse_eye_resolution(a.resolution);
  reference::FixedFunctionRun run;
  run.first_frame = a.frame;
  run.frames = a.frames;
  run.width = window.eye_width;
  run.height = window.eye_height;
  Image last;
  try {
    last = reference::draw_fixed_function(scene, run);
  } catch (const reference::Unavailable& e) {
    fmt::print("SKIPPED: no OpenGL compatibility context: {}\n", e.what());
    return 77;
  }
  if (!a.out.empty()) write_png(last, a.out);
  fmt::print("drew frames {} to {} of {} through OpenGL 1.x at {}x{}\n", a.frame, a.frame + a.frames - 1, scene.name, run.width,
             run.height);
  return 0;
}

int run(const Args& a) {
  if (a.fixed_function && a.time) throw Error("--fixed-function and --time: choose one");
  if (a.fixed_function) return fixed_function(a);
  if (a.time) return time_frames(a);
  if (a.scenes.size() != 1) throw Error("--scene: give exactly one scene (several only with --time)");
  Args one = a;
  one.scene = a.scenes.front();
  const StereoRig rig = parse_frame_resolution(one.resolution);
  // Game levels come from optional packages: without them the comparison is
  // skipped, not failed (scripts/install-deps.sh --game-data installs them).
  if (data_missing(one.scene)) return 77;
  return compare(one, rig);
}

int compare(const Args& a, const StereoRig& rig) {
  Scene scene = load_reference_scene(a.scene);
  if (a.isolate >= 0) {
    // Keep one draw, untextured and white, so that both images are its
    // coverage mask and every differing pixel can be listed.
    if (a.isolate >= int(scene.objects.size()))
      throw Error("--isolate " + std::to_string(a.isolate) + ": the scene has " + std::to_string(scene.objects.size()) +
                  " objects");
    Object o = scene.objects[size_t(a.isolate)];
    Material m = Material::textured("isolated", -1);
    m.two_sided = scene.materials[size_t(o.material)].two_sided;
    scene.materials.push_back(m);
    o.material = int(scene.materials.size()) - 1;
    o.pass = 0;
    o.after.clear();
    scene.objects = {o};
  }
  const StereoView view = make_stereo_view(scene.camera, a.frame, rig);
  std::unique_ptr<reference::GlRenderer> gl;
  try {
    gl = std::make_unique<reference::GlRenderer>();
  } catch (const reference::Unavailable& e) {
    fmt::print("SKIPPED: no OpenGL 4.5 reference renderer: {}\n", e.what());
    return 77;
  }
  const reference::GlFrame ref = gl->render(scene, a.frame, view);
  if (!a.out.empty()) write_png(ref.colour, a.out);
  fmt::print("reference: {}\n", gl->renderer_name());
  if (!a.compare) return 0;

  PipelineSettings settings;
  settings.max_anisotropy = 1;  // the reference samples isotropically
  settings.record_texture_lines = false;
  const auto t0 = std::chrono::steady_clock::now();
  const FrameOutput ours = render_frame(scene, view, settings, a.frame);
  const double ours_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!a.oovr_out.empty()) write_png(ours.colour, a.oovr_out);
  if (!a.diff_out.empty()) write_png(diff_image(ours.colour, ref.colour), a.diff_out);

  std::vector<uint64_t> covered(scene.objects.size() * 2, 0), passed(scene.objects.size() * 2, 0);
  for (const auto& t : ours.trace.tiles) {
    covered[t.object * 2 + t.eye] += t.covered;
    passed[t.object * 2 + t.eye] += t.passed;
  }
  CountStats cov, pas;
  for (size_t i = 0; i < covered.size(); ++i) {
    const std::string name = scene.objects[i / 2].name + (i % 2 ? " right" : " left");
    if (a.list && (covered[i] != ref.counts[i].covered || passed[i] != ref.counts[i].passed))
      fmt::print("  draw {} (object {}) '{}': covered oovr {} GL {}, passed oovr {} GL {}\n", i, i / 2, name, covered[i],
                 ref.counts[i].covered, passed[i], ref.counts[i].passed);
    accumulate(cov, covered[i], ref.counts[i].covered, name, a.max_draw_diff_percent);
    accumulate(pas, passed[i], ref.counts[i].passed, name, a.max_draw_diff_percent);
  }
  if (a.isolate >= 0) {
    int listed = 0;
    for (int y = 0; y < ours.colour.height; ++y)
      for (int x = 0; x < ours.colour.width; ++x)
        if (ours.colour.pixel(x, y)[0] != ref.colour.pixel(x, y)[0] && listed++ < 40)
          fmt::print("  pixel ({}, {}): oovr {} GL {}\n", x, y, ours.colour.pixel(x, y)[0] ? "covered" : "empty",
                     ref.colour.pixel(x, y)[0] ? "covered" : "empty");
  }
  const double psnr = psnr_rgb(ours.colour, ref.colour);
  // The file name tells models of the same name apart (Wuson.ac, Wuson.ply).
  const std::string label = std::filesystem::path(a.scene).filename().string();
  fmt::print("{} frame {} {}x{}: PSNR {:.2f} dB (threshold {:.1f})\n", label, a.frame, view.frame_width, view.frame_height, psnr,
             a.min_psnr);
  fmt::print("  time: llvmpipe {:.0f} ms, oovr {:.0f} ms (image and counts; oovr without texture-line recording)\n",
             ref.render_ms, ours_ms);
  print_counts("covered", cov, a.max_draw_diff_percent);
  print_counts("passed ", pas, a.max_draw_diff_percent);
  // Covered fragments are the rasteriser's output and must match draw by
  // draw. Passed fragments also depend on filtered alpha at the alpha test's
  // cutoff, where the two renderers' filtering arithmetic may decide
  // differently and change depth-test outcomes of later draws by a few
  // fragments: they must match in total (docs/validation.md).
  const double passed_total = pas.gl ? std::abs(double(pas.oovr) - double(pas.gl)) / double(pas.gl) * 100.0 : 0.0;
  // Two empty frames match perfectly and prove nothing: the frame must show
  // the scene (passed fragments for at least 1% of its pixels; a camera or
  // loader that draws nothing fails here), unless one object is isolated.
  const double drawn = double(pas.gl) / (double(view.frame_width) * double(view.frame_height));
  const bool shows = a.isolate >= 0 || drawn >= 0.01;
  fmt::print("  drawn: {:.2f} passed fragments per pixel{}\n", drawn, shows ? "" : ", too few to compare (at least 0.01)");
  const bool ok = shows && psnr >= a.min_psnr && cov.over == 0 && passed_total <= a.max_draw_diff_percent;
  fmt::print("{}\n", ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"oovr-reference: render with Mesa llvmpipe and compare with oovr's pipeline"};
  Args a;
  app.add_option("--scene", a.scenes, "Scene name or model file (with --time: repeatable)")->required();
  app.add_option("--frame", a.frame, "Frame of the camera path")->check(CLI::NonNegativeNumber);
  app.add_option("--resolution", a.resolution, "Whole stereo frame WxH (with --fixed-function: the window)")
      ->capture_default_str();
  app.add_option("--out", a.out, "Write llvmpipe's image here (with --fixed-function: the last frame's)");
  app.add_option("--oovr-out", a.oovr_out, "With --compare: write oovr's image here");
  app.add_option("--diff", a.diff_out, "With --compare: write a difference image (x8) here");
  app.add_flag("--compare", a.compare, "Render with oovr too and compare");
  app.add_flag("--list", a.list, "With --compare: list every draw whose counts differ");
  app.add_option("--isolate", a.isolate, "Keep only this object (index), untextured; list differing pixels")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--min-psnr", a.min_psnr, "Fail below this PSNR (dB)")->capture_default_str();
  app.add_flag("--time", a.time, "Measure GPU frame times (GL_TIME_ELAPSED) instead of comparing");
  app.add_flag("--fixed-function", a.fixed_function,
               "Draw the scene as an OpenGL 1.x game does (client arrays, texture environments), mono in a window of "
               "--resolution, frames --frame to --frame + --frames - 1: what the round-trip test captures with apitrace");
  app.add_option("--frames", a.frames, "With --time or --fixed-function: frames from --frame on")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  app.add_option("--resolutions", a.resolutions, "With --time: comma-separated stereo frame sizes (default: --resolution)");
  app.add_option("--repeat", a.repeat, "With --time: timed repetitions per frame (median)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--aniso", a.aniso, "With --time: maximum anisotropic filtering taps")
      ->capture_default_str()
      ->check(CLI::Range(1, 16));
  app.add_option("--csv", a.csv, "With --time: write the frames here (default: standard output)");
  app.add_option("--platform", a.platform,
                 "With --time: 'gpu' (a GPU through EGL's device platform, else llvmpipe) or 'llvmpipe'")
      ->capture_default_str()
      ->check(CLI::IsMember({"gpu", "llvmpipe"}));
  app.add_option("--max-draw-diff", a.max_draw_diff_percent,
                 "Fail when a draw's covered fragments, or all passed fragments, differ by more (%)")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
    return run(a);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "oovr-reference: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "oovr-reference: error: %s\n", e.what());
    return 1;
  }
}
