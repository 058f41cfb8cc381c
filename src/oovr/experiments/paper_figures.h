// Internal to the paper evaluation (paper.cpp, paper_doc.cpp): what is run
// and the figures' numbers computed from the runs.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "oovr/experiments/paper.h"

namespace oovr::paper {

// Every scheme of Figure 15, the bounds and the SMP comparison.
inline const std::vector<std::string> kSchemes = {"baseline", "baseline-1tb", "afr",        "sfr-v", "sfr-h",   "object",
                                           "oo-app",   "oo-vr",        "single-gpm", "ideal", "two-pass"};
// Figure 17 and 18: the baseline, object-level SFR and OO-VR.
inline const std::vector<std::string> kSweepSchemes = {"baseline", "object", "oo-vr"};
inline const std::vector<std::pair<std::string, double>> kLinks = {
    {"32GBps", 32}, {"64GBps", 64}, {"128GBps", 128}, {"256GBps", 256}, {"512GBps", 512}, {"1TBps", 1000}};
inline const std::vector<int> kGpms = {1, 2, 4, 8, 16};
// Ablations: each mechanism taken out of OO-VR, and added to OO_APP.
inline const std::vector<std::pair<std::string, std::string>> kMechanisms = {
    {"predictor", "oo.predictor"}, {"pre-allocation", "oo.prealloc"}, {"split", "oo.split"}, {"DHC", "oo.composition"}};

inline std::string off_value(const std::string& key) { return key == "oo.composition" ? "root" : "false"; }
inline std::string on_value(const std::string& key) { return key == "oo.composition" ? "distributed" : "true"; }

inline std::string link_variant(const std::string& bw) { return bw == "64GBps" ? "" : "link.bandwidth=" + bw; }
inline std::string gpm_variant(int n) { return n == 4 ? "" : "gpms=" + std::to_string(n); }


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
  double traffic(const std::string& scene, const std::string& res, const std::string& scheme, const std::string& against = "baseline") const {
    const SchemeResult* a = r.find(scene, res, scheme);
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
