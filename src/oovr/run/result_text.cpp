#include "oovr/run/result_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "oovr/run/result_metrics.h"

#include "oovr/scene/formats/gl_trace.h"

namespace oovr {

namespace {

std::string mb(uint64_t b) { return fmt::format("{:.2f} MB", double(b) / 1e6); }

const SchemeResult* baseline_of(const std::vector<SchemeResult>& results) {
  for (const auto& r : results)
    if (r.scheme == "baseline") return &r;
  return nullptr;
}

}  // namespace

std::vector<ComparisonRow> comparison_rows(const std::vector<SchemeResult>& results) {
  const SchemeResult* base = baseline_of(results);
  std::vector<ComparisonRow> rows;
  for (const auto& r : results) {
    ComparisonRow row;
    row.scheme = r.scheme;
    row.latency_ms = r.frame_latency_s * 1e3;
    row.frames_per_s = r.throughput_fps;
    row.inter_gpm_mb = double(r.total_inter_gpm_bytes()) / 1e6;
    row.best_to_worst = r.best_to_worst();
    if (const Energy e = energy_of(r); e.known) row.energy_mj = e.total() * 1e3;
    if (base) {
      row.speedup = base->frame_latency_s / r.frame_latency_s;
      row.throughput_ratio = r.throughput_fps / base->throughput_fps;
      // The CLI has always shown 0.00x here when the baseline moved nothing.
      row.traffic_ratio =
          base->total_inter_gpm_bytes() ? double(r.total_inter_gpm_bytes()) / double(base->total_inter_gpm_bytes()) : 0.0;
    }
    rows.push_back(row);
  }
  return rows;
}

std::string frame_range(int first, int frames) {
  return frames > 1 ? fmt::format("frames {} to {}", first, first + frames - 1) : fmt::format("frame {}", first);
}

// For a captured game: which of the game's frames were measured and what
// they drew (the game's draw calls; the depth clears oovr adds are not
// counted). Empty for other scenes.
std::string captured_frames_text(const Scene& scene, int first, int frames) {
  if (!scene.captured()) return "";
  std::vector<uint64_t> draws;
  uint64_t screen = 0;
  for (int k = 0; k < frames; ++k) {
    const GameDraws g = game_draws(scene, first + k);
    draws.push_back(g.draws);
    screen += g.screen;
  }
  std::vector<uint64_t> sorted = draws;
  std::sort(sorted.begin(), sorted.end());
  const int path = int(scene.camera.frames.size());
  return fmt::format("  the game's {}: draws per frame median {} ({} to {}), {:.0f} of them 2-D\n",
                     frame_range(scene.capture_first_frame + first % path, frames), sorted[sorted.size() / 2], sorted.front(),
                     sorted.back(), double(screen) / double(frames));
}

std::string comparison_text(const Simulation& s) {
  const FrameWindow& f = *s.window;
  const bool base = baseline_of(s.results) != nullptr;
  std::string out = fmt::format("{}: {}, {}x{} stereo, {} GPMs; {}{}\n", f.scene->name, frame_range(s.frame, s.frames),
                                f.rig.frame_width(), f.rig.frame_height(), s.results.front().gpms,
                                s.frames > 1 ? "means per frame" : "one frame", base ? ", ratios against baseline" : "");
  out += captured_frames_text(*f.scene, s.frame, s.frames);
  size_t w = 13;  // the scheme column fits the longest name
  for (const auto& r : s.results) w = std::max(w, r.scheme.size());
  out += fmt::format("  {:<{}} {:>10} {:>9} {:>9} {:>10} {:>9} {:>11} {:>8} {:>9}\n", "scheme", w, "latency ms", "speed-up",
                     "frames/s", "throughput", "inter-GPM", "traffic", "best/worst", "energy mJ");
  // Without the baseline in the list there is nothing to normalise to.
  const auto ratio = [&](double v) { return base ? fmt::format("{:.2f}x", v) : std::string("-"); };
  for (const ComparisonRow& r : comparison_rows(s.results))
    out += fmt::format("  {:<{}} {:>10.3f} {:>9} {:>9.1f} {:>10} {:>9} {:>11} {:>8.2f} {:>9}\n", r.scheme, w, r.latency_ms,
                       ratio(r.speedup), r.frames_per_s, ratio(r.throughput_ratio), fmt::format("{:.2f} MB", r.inter_gpm_mb),
                       ratio(r.traffic_ratio), r.best_to_worst,
                       std::isnan(r.energy_mj) ? std::string("-") : fmt::format("{:.3f}", r.energy_mj));
  return out;
}

std::string simulation_text(const Simulation& s, size_t i) {
  const FrameWindow& f = *s.window;
  const SchemeResult& r = s.results.at(i);
  std::string out =
      fmt::format("{}: {} on {} GPMs, {}, {}x{} stereo{}\n", f.scene->name, r.scheme, r.gpms, frame_range(s.frame, s.frames),
                  f.rig.frame_width(), f.rig.frame_height(), s.frames > 1 ? "; means per frame" : "");
  out += captured_frames_text(*f.scene, s.frame, s.frames);
  out += fmt::format("  frame latency   {:.0f} cycles ({:.3f} ms)\n", r.frame_latency_cycles(), r.frame_latency_s * 1e3);
  out += fmt::format("  throughput      {:.1f} frames/s{}\n", r.throughput_fps,
                     r.frames_in_flight > 1 ? fmt::format(" ({} frames in flight)", r.frames_in_flight) : "");
  out += "  GPM busy        ";
  for (size_t g = 0; g < r.gpm_busy_s.size(); ++g)
    out += fmt::format("{}gpm{} {:.0f}", g ? ", " : "", g, r.gpm_busy_s[g] * r.frequency_hz);
  out += fmt::format(" cycles\n  best-to-worst   {:.2f}\n", r.best_to_worst());
  out += fmt::format("  inter-GPM bytes {}", mb(r.total_inter_gpm_bytes()));
  bool first = true;
  for (int c = 0; c < kCategories; ++c)
    if (r.inter_gpm_bytes[size_t(c)]) {
      out += fmt::format("{}{} {}", first ? ": " : ", ", category_name(Category(c)), mb(r.inter_gpm_bytes[size_t(c)]));
      first = false;
    }
  out += fmt::format("\n  DRAM bytes      {} (all GPMs, read and written)\n", mb(r.local_dram_bytes));
  out +=
      fmt::format("  front ends      {} draws received, {} vertices transformed (all GPMs, all frames)\n", r.draws, r.vertices);
  out += fmt::format("  footprint       {} resident in GPM memories\n", mb(r.footprint_bytes));
  if (const Energy e = energy_of(r); e.known)
    out += fmt::format(
        "  energy          {:.3f} mJ: caches {:.3f}, DRAM {:.3f}, links {:.3f} (moving data; not the SMs' arithmetic)\n",
        e.total() * 1e3, e.caches * 1e3, e.dram * 1e3, e.links * 1e3);
  for (const auto& n : r.notes) out += fmt::format("  note: {}\n", n);
  if (s.frames > 1) {
    out += "  frame latencies ";
    for (size_t k = 0; k < r.frame_latencies_s.size(); ++k)
      out += fmt::format("{}{:.0f}", k ? ", " : "", r.frame_latencies_s[k] * r.frequency_hz);
    out += " cycles\n";
  }
  return out;
}

std::string timing_text(const Simulation& s) {
  std::string out = fmt::format("  time: traces {:.0f} ms ({} of {} from the cache), simulation {:.0f} ms\n", s.trace_s * 1e3,
                                s.window->cached, s.window->frames->size(), s.simulation_s * 1e3);
  for (const auto& n : s.window->notes) out += fmt::format("  note: {}\n", n);
  return out;
}

}  // namespace oovr
