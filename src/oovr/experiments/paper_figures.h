// Internal to the paper evaluation (paper.cpp, paper_doc.cpp): what is run
// and the figures' numbers computed from the runs.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "oovr/experiments/paper.h"
#include "oovr/memory/memory_spec.h"

namespace oovr::paper {

// Figure 17 and 18: the baseline, object-level SFR and OO-VR.
inline const std::vector<std::string> kSweepSchemes = {"baseline", "object", "oo-vr"};
inline const std::vector<std::pair<std::string, double>> kLinks = {{"32GBps", 32},   {"64GBps", 64},   {"128GBps", 128},
                                                                   {"256GBps", 256}, {"512GBps", 512}, {"1TBps", 1000}};
inline const std::vector<int> kGpms = {1, 2, 4, 8, 16};
// Ablations: each mechanism taken out of OO-VR, and added to OO_APP.
inline const std::vector<std::pair<std::string, std::string>> kMechanisms = {
    {"predictor", "oo.predictor"}, {"pre-allocation", "oo.prealloc"}, {"split", "oo.split"}, {"DHC", "oo.composition"}};

inline std::string off_value(const std::string& key) { return key == "oo.composition" ? "root" : "false"; }
inline std::string on_value(const std::string& key) { return key == "oo.composition" ? "distributed" : "true"; }

// Named whatever the machine's own value: PaperResults::find takes a
// setting equal to the machine's as none (the main runs).
inline std::string link_variant(const std::string& bw) { return "link.bandwidth=" + bw; }
inline std::string gpm_variant(int n) { return "gpms=" + std::to_string(n); }

// The model's steps from ca88d23 to now (issue 9; the document's "Before
// and after" table): each switches on one change on top of the ones before,
// through the configuration keys that keep the earlier behaviour; the last
// step is the model as it is (the main runs). Every step keeps OO-VR's
// copies in the GPMs' DRAM (8 GB, where every scene's copies fit): the
// earlier "bounded copies" step, an assumed 16 MB per GPM, is gone, and
// what a cap does is the copy capacity section's (kCopyCapacities). The fixed defects (two-pass
// and object-level SFR transforming every draw, remote caches ending at
// draws, OO_APP without the engine's queue, the even deal, hand-offs with
// link latency) cannot be switched off: they are in every step.
struct ModelStep {
  std::string label;
  std::string change;    // what the step changes, for the document
  std::string baseline;  // the scheme every claim is measured against
  std::string settings;  // ';'-separated overrides: the changes not made yet
};
inline const std::vector<ModelStep> kSteps = {
    {"defects fixed", "ca88d23's model with its defects fixed; the baseline still deals framebuffer pages", "baseline-paged",
     "timing.sharing=equal;gpm.requests_in_flight=0;gpm.draw_cycles=0;composition.payload=colour+depth"},
    {"paper's baseline", "the baseline deals tiles one by one, so its GPMs share colour and depth pages", "baseline",
     "timing.sharing=equal;gpm.requests_in_flight=0;gpm.draw_cycles=0;composition.payload=colour+depth"},
    {"colour composition", "sort-last schemes send colour only and depth-test in the final frame's buffer", "baseline",
     "timing.sharing=equal;gpm.requests_in_flight=0;gpm.draw_cycles=0"},
    {"fair sharing", "shared resources are shared work-conservingly (max-min)", "baseline",
     "gpm.requests_in_flight=0;gpm.draw_cycles=0"},
    {"reads in flight", "every read holds one of `gpm.requests_in_flight` request slots per SM for its latency", "baseline",
     "gpm.draw_cycles=0"},
    {"per-draw front end",
     "every GPM receiving a draw spends `gpm.draw_cycles` on it, up to `gpm.draws_ahead` draws ahead of its pipeline (oovr now)",
     "baseline", ""},
};
// OO-VR's copies capped per GPM (memory.copies.capacity), at the sweep
// resolution; the main runs, uncapped in the GPMs' DRAM, are the last point.
inline const std::vector<std::pair<std::string, double>> kCopyCapacities = {
    {"16MB", 16.0 * (1 << 20)}, {"64MB", 64.0 * (1 << 20)}, {"256MB", 256.0 * (1 << 20)}, {"1GB", double(1 << 30)}};
// The runs with copies capped at `cap`; "" names the uncapped main runs.
inline std::string copy_variant(const std::string& cap) { return cap.empty() ? "" : "memory.copies.capacity=" + cap; }
// The capped points, then the main runs' ("", at the DRAM's `dram_bytes`).
inline std::vector<std::pair<std::string, double>> copy_points(double dram_bytes) {
  std::vector<std::pair<std::string, double>> v = kCopyCapacities;
  v.push_back({"", dram_bytes});
  return v;
}
// A figure a scheme reported of itself (NaN when it did not).
inline double scheme_metric(const SchemeResult& r, const std::string& name) {
  const Stat* s = r.stats.find(r.scheme, name);
  return s ? s->value : std::nan("");
}

// What each step runs at the sweep resolution (scheme, extra overrides).
inline std::vector<std::pair<std::string, std::string>> step_runs(const ModelStep& step) {
  const std::string& b = step.baseline;
  return {{b, ""},
          {b, "link.bandwidth=1TBps"},
          {b, "link.bandwidth=32GBps"},
          {b, "gpms=8"},
          {"afr", ""},
          {"sfr-v", ""},
          {"sfr-h", ""},
          {"object", ""},
          {"object", "gpms=8"},
          {"oo-app", ""},
          {"oo-vr", ""},
          {"oo-vr", "link.bandwidth=1TBps"},
          {"oo-vr", "link.bandwidth=32GBps"},
          {"oo-vr", "gpms=8"},
          {"single-gpm", ""},
          {"two-pass", ""}};
}
// The one-pass workloads (issue 10's comparison): a game level drawn as
// oovr drew it before real materials, one opaque pass of its first image
// times its lightmap (the scene option below, for the sources that take
// it), with textures stored as RGBA8 and every fragment costing 32
// instructions. The workload section sets the claims on these beside the
// same levels with their real materials.
inline const std::string kOnePassOption = "materials=one-pass";
inline const std::string kOnePassWindow = "pipeline.texture_format=rgba8";
inline const std::string kOnePassVariant = "shader.fragment_instructions=32";
inline std::string one_pass_scene(const std::string& scene) {
  return scene + (scene.find('?') == std::string::npos ? "?" : "&") + kOnePassOption;
}

// The variant name of a step's run: its settings, then the extra ones.
inline std::string step_variant(const ModelStep& step, const std::string& extra) {
  if (step.settings.empty()) return extra;
  return extra.empty() ? step.settings : step.settings + ";" + extra;
}
// A key's value on the evaluation's machine, as it reads ("64 GB/s").
inline std::string machine_value(const PaperOptions& o, const std::string& key) {
  const auto it = o.spec.entries.find(key);
  return it == o.spec.entries.end() ? "n/a" : it->second.value;
}

// How a document at `doc` links the plots in `plots_dir` (empty: none):
// relative to the document's folder, else absolute.
std::string plots_link(const std::string& doc, const std::string& plots_dir);

inline double geomean(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0;
  for (double x : v) s += std::log(x);
  return std::exp(s / double(v.size()));
}

// The figures' numbers, shared by the CSV, SVG and document writers.
struct Figures {
  const PaperResults& r;
  const PaperOptions& o;
  double speedup(const std::string& scene, const std::string& res, const std::string& scheme, const std::string& variant = "",
                 const std::string& against = "baseline", const std::string& against_variant = "") const {
    const SchemeResult* a = r.find(scene, res, scheme, variant);
    const SchemeResult* b = r.find(scene, res, against, against_variant);
    return a && b ? b->frame_latency_s / a->frame_latency_s : std::nan("");
  }
  // The lowest and highest of the frame-by-frame speed-ups (the reference's
  // frame k over the run's), where both measured the same frames; NaNs
  // otherwise. Figure 15's whiskers.
  std::pair<double, double> speedup_range(const std::string& scene, const std::string& res, const std::string& scheme) const {
    const SchemeResult* a = r.find(scene, res, scheme);
    const SchemeResult* b = r.find(scene, res, "baseline");
    double lo = std::nan(""), hi = std::nan("");
    if (!a || !b || a->frame_latencies_s.size() != b->frame_latencies_s.size()) return {lo, hi};
    for (size_t k = 0; k < a->frame_latencies_s.size(); ++k) {
      if (!(a->frame_latencies_s[k] > 0)) continue;
      const double x = b->frame_latencies_s[k] / a->frame_latencies_s[k];
      lo = std::isnan(lo) ? x : std::min(lo, x);
      hi = std::isnan(hi) ? x : std::max(hi, x);
    }
    return {lo, hi};
  }
  double traffic(const std::string& scene, const std::string& res, const std::string& scheme,
                 const std::string& against = "baseline", const std::string& variant = "") const {
    const SchemeResult* a = r.find(scene, res, scheme, variant);
    const SchemeResult* b = r.find(scene, res, against);
    return a && b && b->total_inter_gpm_bytes() ? double(a->total_inter_gpm_bytes()) / double(b->total_inter_gpm_bytes())
                                                : std::nan("");
  }
  // Figure 17: speed-up over the baseline with 64 GB/s links.
  double link(const std::string& scene, const std::string& scheme, const std::string& bw) const {
    return speedup(scene, o.sweep_resolution, scheme, link_variant(bw));
  }
  // Figure 18: speed-up over one GPM (the single-GPU system).
  double gpms(const std::string& scene, const std::string& scheme, int n) const {
    return speedup(scene, o.sweep_resolution, scheme, gpm_variant(n), "single-gpm");
  }
  // OO-VR with its copies capped at `cap` ("": uncapped, the main run)
  // against the baseline.
  double copies_speedup(const std::string& scene, const std::string& cap) const {
    return speedup(scene, o.sweep_resolution, "oo-vr", copy_variant(cap));
  }
  double copies_traffic(const std::string& scene, const std::string& cap) const {
    return traffic(scene, o.sweep_resolution, "oo-vr", "baseline", copy_variant(cap));
  }
  // What OO-VR's copies may take per GPM in the main runs: the machine's
  // cap (memory.copies.capacity), else its DRAM (uncapped).
  double dram_bytes() const {
    return double(o.spec.memory.copy_capacity.value ? o.spec.memory.copy_capacity.value : o.spec.memory.dram_capacity.value);
  }
  bool copies_capped() const { return o.spec.memory.copy_capacity.value != 0; }
  std::vector<double> across(const std::function<double(const std::string&)>& f) const {
    std::vector<double> v;
    for (const auto& s : r.scenes) {
      const double x = f(s);
      if (std::isfinite(x) && x > 0) v.push_back(x);
    }
    return v;
  }
  double mean(const std::function<double(const std::string&)>& f) const { return geomean(across(f)); }
};

}  // namespace oovr::paper
