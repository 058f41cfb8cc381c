// oovr correlate: oovr's frame times beside a real GPU's (experiments/hardware.h).
#include <fmt/core.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/experiments/hardware.h"
#include "oovr/run/result_json.h"

namespace oovr::cli {
namespace {

// What the GPU drew, for the first line of the output.
std::string workload(const HardwareWorkload& w) {
  return fmt::format("{} materials, {} textures, anisotropy {}, scenes of oovr {}", w.materials, w.texture_format, w.aniso,
                     w.commit);
}

// Calibration: the correlation at each value of one key; the value that
// makes oovr most nearly proportional to the GPU (the smallest standard
// deviation of log(oovr / GPU) over the points) is named; then how general
// that is: each scene left out of the fit in turn.
int sweep(const CorrelateArgs& a, const HardwareData& data, CorrelationOptions o) {
  const size_t eq = a.sweep.find('=');
  if (eq == std::string::npos || eq == 0) throw Error("--sweep '" + a.sweep + "' must be key=v1,v2,...");
  const std::string key = a.sweep.substr(0, eq);
  const std::vector<std::string> values = split_list(a.sweep.substr(eq + 1));
  if (values.empty()) throw Error("--sweep '" + a.sweep + "' names no value");
  fmt::print("{} ({}; {}): {} on {} frames, sweeping {}\n", a.hardware,
             data.renderer.empty() ? "renderer not named" : data.renderer, workload(data.workload), a.scheme, data.frames.size(),
             key);
  fmt::print("  {:>14} {:>10} {:>9} {:>12}\n", "value", "Pearson r", "spread", "sd log ratio");
  std::string best;
  double best_sd = 0;
  const Config base = o.config;
  std::vector<Correlation> runs;
  for (const auto& v : values) {
    o.config = base;
    o.config.set(key, v);
    runs.push_back(correlate(data, o));
    const Correlation& c = runs.back();
    fmt::print("  {:>14} {:>10.3f} {:>8.2f}x {:>12.3f}\n", v, c.r, c.spread, c.log_sd);
    if (best.empty() || c.log_sd < best_sd) {
      best = v;
      best_sd = c.log_sd;
    }
  }
  fmt::print("  most proportional: {} = {}\n", key, best);
  if (runs.front().r_within.size() >= 2) {
    fmt::print("  leave one scene out: fitted on the other scenes, the ratio oovr/GPU of the scene left out against theirs\n");
    const std::vector<LeftOut> left = leave_one_scene_out(values, runs);
    size_t w = 8;
    for (const LeftOut& l : left) w = std::max(w, l.scene.size());
    fmt::print("  {:<{}} {:>14} {:>16} {:>10} {:>9}\n", "left out", w, "fitted value", "its ratio/theirs", "r (all)", "spread");
    for (const LeftOut& l : left)
      fmt::print("  {:<{}} {:>14} {:>15.2f}x {:>10.3f} {:>8.2f}x\n", l.scene, w, l.value, l.held_out, l.r, l.spread);
  }
  return 0;
}

}  // namespace

int correlate(const CorrelateArgs& a) {
  // An unwritable output fails now, not after the simulation.
  if (!a.json.empty()) check_output_path(a.json, "JSON output");
  const HardwareData data = HardwareData::read(a.hardware);
  CorrelationOptions o;
  o.scheme = a.scheme;
  o.config = machine_config(a.config, a.settings);
  o.use_cache = !a.no_cache;
  if (!a.sweep.empty()) return sweep(a, data, o);
  const Correlation c = correlate(data, o);
  fmt::print("{} ({}; {}): {} on {} points, {} frames; medians per point, times in microseconds\n", a.hardware,
             data.renderer.empty() ? "renderer not named" : data.renderer, workload(data.workload), c.scheme, c.points.size(),
             data.frames.size());
  size_t w = 5;  // the scene column: as wide as its longest name
  for (const auto& p : c.points) w = std::max(w, p.scene.size());
  fmt::print("  {:<{}} {:>10} {:>7} {:>9} {:>9} {:>9}\n", "scene", w, "resolution", "frames", "GPU", "oovr", "oovr/GPU");
  double lo = 0, hi = 0;
  for (const auto& p : c.points) {
    fmt::print("  {:<{}} {:>10} {:>7} {:>9.1f} {:>9.1f} {:>9.3f}\n", p.scene, w, p.resolution, p.frames.size(), p.gpu_median_us,
               p.oovr_median_us, p.ratio());
    lo = lo == 0 ? p.ratio() : std::min(lo, p.ratio());
    hi = std::max(hi, p.ratio());
  }
  fmt::print("  Pearson r of the medians {:.3f}; oovr/GPU from {:.3f} to {:.3f}: spread {:.2f}x (sd of log ratio {:.3f})\n", c.r,
             lo, hi, c.spread, c.log_sd);
  fmt::print("  within each scene (every frame, all resolutions):");
  bool first = true;
  for (const auto& [scene, r] : c.r_within) {
    fmt::print("{} {} r {:.3f}", first ? "" : ",", scene, r);
    first = false;
  }
  fmt::print("\n");
  if (a.per_frame) {
    fmt::print("  {:<{}} {:>10} {:>6} {:>9} {:>9} {:>9}\n", "scene", w, "resolution", "frame", "GPU", "oovr", "oovr/GPU");
    for (const auto& p : c.points)
      for (size_t i = 0; i < p.frames.size(); ++i)
        fmt::print("  {:<{}} {:>10} {:>6} {:>9.1f} {:>9.1f} {:>9.3f}\n", p.scene, w, p.resolution, p.frames[i], p.gpu_us[i],
                   p.oovr_us[i], p.oovr_us[i] / p.gpu_us[i]);
  }
  for (const auto& n : c.notes) fmt::print("  note: {}\n", n);
  if (!a.json.empty()) {
    nlohmann::ordered_json j = results_header(a.command);  // docs/results.md
    j["hardware"] = a.hardware;
    j["renderer"] = data.renderer;
    j["workload"] = {{"commit", data.workload.commit},
                     {"materials", data.workload.materials},
                     {"texture_format", data.workload.texture_format},
                     {"aniso", data.workload.aniso}};
    j["scheme"] = c.scheme;
    j["pearson_r"] = c.r;
    j["ratio_spread"] = c.spread;
    j["log_ratio_sd"] = c.log_sd;
    nlohmann::ordered_json within = nlohmann::ordered_json::object();
    for (const auto& [scene, r] : c.r_within) within[scene] = r;
    j["pearson_r_within_scene"] = within;
    nlohmann::ordered_json points = nlohmann::ordered_json::array();
    for (const auto& p : c.points)
      points.push_back({{"scene", p.scene},
                        {"resolution", p.resolution},
                        {"frames", p.frames},
                        {"gpu_us", p.gpu_us},
                        {"oovr_us", p.oovr_us},
                        {"gpu_median_us", p.gpu_median_us},
                        {"oovr_median_us", p.oovr_median_us}});
    j["points"] = points;
    j["notes"] = c.notes;
    write_output_file(a.json, j.dump(2) + "\n", "JSON output");
  }
  if (a.min_r > -1 && !(c.r >= a.min_r))
    throw Error(fmt::format("Pearson r of the medians is {:.3f}, below --min-r {}", c.r, a.min_r));
  if (a.max_spread > 0 && !(c.spread <= a.max_spread))
    throw Error(fmt::format("the ratio oovr/GPU spreads {:.2f}x, more than --max-spread {}", c.spread, a.max_spread));
  return 0;
}

}  // namespace oovr::cli
