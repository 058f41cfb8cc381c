// oovr simulate / oovr compare: render a scene's frames once, replay them
// through one or several schemes, and print (or write as JSON) the results.
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/parallel.h"
#include "oovr/core/text.h"
#include "oovr/experiments/frames.h"
#include "oovr/experiments/result_images.h"
#include "oovr/experiments/result_json.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/load.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr::cli {
namespace {

std::string mb(uint64_t b) { return fmt::format("{:.2f} MB", double(b) / 1e6); }

using Frames = FrameWindow;

// The traces of the window from a.frame, from the cache when there.
Frames render_frames(const SimulateArgs& a, const Config& config, int count, bool need_first_image = false) {
  WindowRequest r;
  r.first = a.frame;
  r.count = count;
  r.aniso = a.aniso;
  r.use_cache = !a.no_cache;
  r.need_first_image = need_first_image;
  return load_window(load_scene(a.scene),
                     a.eye_resolution.empty() ? parse_frame_resolution(a.resolution) : parse_eye_resolution(a.eye_resolution),
                     config, r);
}

void print_result(const SchemeResult& r) {
  fmt::print("  frame latency   {:.0f} cycles ({:.3f} ms)\n", r.frame_latency_cycles(), r.frame_latency_s * 1e3);
  fmt::print("  throughput      {:.1f} frames/s{}\n", r.throughput_fps,
             r.frames_in_flight > 1 ? fmt::format(" ({} frames in flight)", r.frames_in_flight) : "");
  fmt::print("  GPM busy        ");
  for (size_t g = 0; g < r.gpm_busy_s.size(); ++g)
    fmt::print("{}gpm{} {:.0f}", g ? ", " : "", g, r.gpm_busy_s[g] * r.frequency_hz);
  fmt::print(" cycles\n  best-to-worst   {:.2f}\n", r.best_to_worst());
  fmt::print("  inter-GPM bytes {}", mb(r.total_inter_gpm_bytes()));
  bool first = true;
  for (int c = 0; c < kCategories; ++c)
    if (r.inter_gpm_bytes[size_t(c)]) {
      fmt::print("{}{} {}", first ? ": " : ", ", category_name(Category(c)), mb(r.inter_gpm_bytes[size_t(c)]));
      first = false;
    }
  fmt::print("\n  DRAM bytes      {} (all GPMs, read and written)\n", mb(r.local_dram_bytes));
  fmt::print("  front ends      {} draws received, {} vertices transformed (all GPMs, all frames)\n", r.draws, r.vertices);
  fmt::print("  footprint       {} resident in GPM memories\n", mb(r.footprint_bytes));
  for (const auto& n : r.notes) fmt::print("  note: {}\n", n);
}

void write_json(const std::string& path, const nlohmann::ordered_json& j) {
  write_output_file(path, j.dump(2) + "\n", "JSON output");
}

}  // namespace

Config machine_config(const std::string& file, const std::vector<std::string>& settings) {
  Config c = file.empty() ? Config{} : Config::from_toml_file(file);
  for (const auto& s : settings) c.set(s);
  return c;
}

namespace {

int window_of(const SimulateArgs& a, const Config& config, const std::vector<std::string>& schemes) {
  return measured_window(schemes, config, a.frames, "--frames");
}

std::string frame_range(int first, int window) {
  return window > 1 ? fmt::format("frames {} to {}", first, first + window - 1) : fmt::format("frame {}", first);
}

}  // namespace

int simulate(const SimulateArgs& a) {
  // Outputs are checked before any work, and may not share a path.
  OutputPaths outputs;
  if (!a.json.empty()) {
    check_output_path(a.json, "JSON output");
    outputs.claim(a.json, "JSON output (--json)");
  }
  if (!a.gpm_image.empty()) {
    check_image_path(a.gpm_image);
    outputs.claim(a.gpm_image, "GPM image (--gpm-image)");
  }
  if (!a.traffic_image.empty()) {
    check_image_path(a.traffic_image);
    outputs.claim(a.traffic_image, "traffic image (--traffic-image)");
  }
  const Config config = machine_config(a.config, a.settings);
  const int window = window_of(a, config, {a.scheme});
  const auto t0 = std::chrono::steady_clock::now();
  const Frames f = render_frames(a, config, window, !a.gpm_image.empty() || !a.traffic_image.empty());
  const auto t1 = std::chrono::steady_clock::now();
  const SchemeResult r = run_scheme_window(a.scheme, f.scene, *f.frames, config, window);
  const auto t2 = std::chrono::steady_clock::now();
  fmt::print("{}: {} on {} GPMs, {}, {}x{} stereo{}\n", f.scene.name, r.scheme, r.gpms, frame_range(a.frame, window),
             f.rig.frame_width(), f.rig.frame_height(), window > 1 ? "; means per frame" : "");
  print_result(r);
  if (window > 1) {
    fmt::print("  frame latencies ");
    for (size_t k = 0; k < r.frame_latencies_s.size(); ++k)
      fmt::print("{}{:.0f}", k ? ", " : "", r.frame_latencies_s[k] * r.frequency_hz);
    fmt::print(" cycles\n");
  }
  fmt::print("  time: traces {:.0f} ms ({} of {} from the cache), simulation {:.0f} ms\n",
             std::chrono::duration<double, std::milli>(t1 - t0).count(), f.cached, f.frames->size(),
             std::chrono::duration<double, std::milli>(t2 - t1).count());
  for (const auto& n : f.notes) fmt::print("  note: {}\n", n);
  if (!a.json.empty())
    write_json(a.json, results_document(a.command, f.scene.name, a.frame, window, f.rig, config, {r}, f.notes));
  if (!a.gpm_image.empty()) write_image(gpm_image(f.outputs.front(), r), a.gpm_image);
  if (!a.traffic_image.empty()) write_image(traffic_image(f.outputs.front(), r), a.traffic_image);
  return 0;
}

int compare(const SimulateArgs& a, const std::vector<std::string>& schemes) {
  if (!a.json.empty()) check_output_path(a.json, "JSON output");
  const Config config = machine_config(a.config, a.settings);
  const int window = window_of(a, config, schemes);
  const auto t0 = std::chrono::steady_clock::now();
  const Frames f = render_frames(a, config, window);
  const auto t1 = std::chrono::steady_clock::now();
  // Schemes are independent runs: in parallel, each into its own slot.
  std::vector<SchemeResult> results(schemes.size());
  parallel_for(schemes.size(), 0,
               [&](size_t i) { results[i] = run_scheme_window(schemes[i], f.scene, *f.frames, config, window); });
  const auto t2 = std::chrono::steady_clock::now();
  const SchemeResult* base = nullptr;
  for (const auto& r : results)
    if (r.scheme == "baseline") base = &r;
  fmt::print("{}: {}, {}x{} stereo, {} GPMs; {}{}\n", f.scene.name, frame_range(a.frame, window), f.rig.frame_width(),
             f.rig.frame_height(), results.front().gpms, window > 1 ? "means per frame" : "one frame",
             base ? ", ratios against baseline" : "");
  size_t w = 13;  // the scheme column fits the longest name
  for (const auto& r : results) w = std::max(w, r.scheme.size());
  fmt::print("  {:<{}} {:>10} {:>9} {:>9} {:>10} {:>9} {:>11} {:>8}\n", "scheme", w, "latency ms", "speed-up", "frames/s",
             "throughput", "inter-GPM", "traffic", "best/worst");
  for (const auto& r : results) {
    const double lat = base ? base->frame_latency_s / r.frame_latency_s : 0;
    const double thr = base ? r.throughput_fps / base->throughput_fps : 0;
    const double traffic =
        base && base->total_inter_gpm_bytes() ? double(r.total_inter_gpm_bytes()) / double(base->total_inter_gpm_bytes()) : 0;
    // Without the baseline in the list there is nothing to normalise to.
    const auto ratio = [&](double v) { return base ? fmt::format("{:.2f}x", v) : std::string("-"); };
    fmt::print("  {:<{}} {:>10.3f} {:>9} {:>9.1f} {:>10} {:>9} {:>11} {:>8.2f}\n", r.scheme, w, r.frame_latency_s * 1e3,
               ratio(lat), r.throughput_fps, ratio(thr), mb(r.total_inter_gpm_bytes()), ratio(traffic), r.best_to_worst());
  }
  fmt::print("  time: traces {:.0f} ms ({} of {} from the cache), simulation {:.0f} ms\n",
             std::chrono::duration<double, std::milli>(t1 - t0).count(), f.cached, window,
             std::chrono::duration<double, std::milli>(t2 - t1).count());
  for (const auto& n : f.notes) fmt::print("  note: {}\n", n);
  if (!a.json.empty())
    write_json(a.json, results_document(a.command, f.scene.name, a.frame, window, f.rig, config, results, f.notes));
  return 0;
}

}  // namespace oovr::cli
