// docs/paper-comparison.md from the runs of `oovr paper`: every figure is
// computed here from the measurements and every number of the paper's comes
// from its claims as data (experiments/paper-claims.toml); the prose states
// only what the numbers next to it show, and says where the paper differs
// and why.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"
#include "oovr/experiments/claims.h"
#include "oovr/experiments/paper.h"
#include "oovr/experiments/paper_figures.h"
#include "oovr/experiments/results_db.h"
#include "oovr/framework/distribution.h"
#include "oovr/framework/oo_spec.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/run/result_metrics.h"

namespace oovr {
namespace fs = std::filesystem;
using namespace paper;

namespace {

std::string pct(double ratio) {
  if (!std::isfinite(ratio)) return "n/a";
  const double p = (ratio - 1) * 100;
  return std::abs(p) < 0.5 ? "0%" : fmt::format("{:+.0f}%", p);
}
std::string times(double ratio) { return std::isfinite(ratio) ? fmt::format("{:.2f}x", ratio) : "n/a"; }
std::string mb(double bytes) { return fmt::format("{:.1f} MB", bytes / 1e6); }

// "a to b" over a list of ratios, as percentages or times.
std::string range(std::vector<double> v, bool as_pct) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return "n/a";
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  const auto f = [&](double x) { return as_pct ? pct(x) : times(x); };
  return *lo == *hi ? f(*lo) : f(*lo) + " to " + f(*hi);
}

// The paper's numbers, from its claims as data (experiments/paper-claims.toml).
const Claim& paper_claim(const std::string& id) {
  for (const Claim& c : paper_claims())
    if (c.id == id) return c;
  throw Error("experiments/paper-claims.toml has no claim " + id);
}
// Claim `id`'s value `label` as a ratio (or bits).
double paper(const std::string& id, const std::string& label) {
  for (const ClaimValue& v : paper_claim(id).values)
    if (v.label == label && v.paper) return *v.paper;
  throw Error("experiments/paper-claims.toml has no number for " + id + " (" + label + ")");
}
// A claim value in its form: "+28%", "1.67x", "960 bits".
std::string in_form(const ClaimValue& v, double x) {
  if (v.form == "percent") return pct(x);
  if (v.form == "bits") return std::isfinite(x) ? fmt::format("{:.0f} bits", x) : "n/a";
  return times(x);
}
// The same as the paper writes it.
std::string paper_text(const std::string& id, const std::string& label) {
  const double v = paper(id, label);
  for (const ClaimValue& x : paper_claim(id).values)
    if (x.label == label) return in_form(x, v);
  return times(v);
}
// A frame-rate loss as a positive percentage: 0.58 -> "42%".
double paper_loss(const std::string& id, const std::string& label) { return (1 - paper(id, label)) * 100; }

// A part of a claim as judged (judge_claims' verdicts `v` of claim `c`):
// whether it has checks, whether all were measured, whether all hold.
struct PartVerdict {
  bool any = false, measured = true, holds = true;
};
PartVerdict part_verdict(const Claim& c, const std::vector<CheckVerdict>& v, const std::string& part) {
  PartVerdict out;
  for (size_t k = 0; k < c.checks.size(); ++k)
    if (c.checks[k].part == part) {
      out.any = true;
      out.measured = out.measured && v[k].measured;
      out.holds = out.holds && v[k].holds;
    }
  return out;
}

class Doc {
 public:
  Doc(const PaperResults& results, const PaperOptions& options, std::string plots_link)
      : r(results), o(options), F{results, options}, plots(std::move(plots_link)) {
    // The claims measured and judged once (claims.h), on the document's
    // scenes at its resolution, relative to the machine the sweep ran.
    std::vector<RunRecord> mine;
    for (const RunRecord& x : r.records)
      if (x.resolution == res() && std::find(r.scenes.begin(), r.scenes.end(), x.scene) != r.scenes.end()) mine.push_back(x);
    const nlohmann::ordered_json machine = machine_values(o.machine);
    measured = measure_claims(paper_claims(), mine, &machine);
    verdicts = judge_claims(paper_claims(), measured);
  }

  std::string write() {
    header();
    claims();
    checks();
    if (o.steps) before_after();
    if (!r.one_pass_scenes.empty()) workloads();
    real_frames();
    figure15();
    figure16();
    figure17();
    figure18();
    ablations();
    if (o.copies) copies();
    agree_and_differ();
    out += "\nThe model's parts, defaults and what they leave out: [model.md](model.md).\n";
    return out;
  }

 private:
  const PaperResults& r;
  const PaperOptions& o;
  Figures F;
  std::string plots;
  std::string out;
  std::vector<std::vector<ClaimMeasured>> measured;
  std::vector<std::vector<CheckVerdict>> verdicts;
  std::set<std::pair<std::string, std::string>> judged;  // (claim, part) the prose has judged
  std::set<std::string> tabled;                          // claims the claims table has a row of
  const std::string& res() const { return o.sweep_resolution; }

  size_t claim_index(const std::string& id) const {
    const auto& claims = paper_claims();
    for (size_t c = 0; c < claims.size(); ++c)
      if (claims[c].id == id) return c;
    throw Error("experiments/paper-claims.toml has no claim " + id);
  }
  const ClaimMeasured& measure(const std::string& id, const std::string& label) const {
    const size_t c = claim_index(id);
    for (size_t k = 0; k < paper_claims()[c].values.size(); ++k)
      if (paper_claims()[c].values[k].label == label) return measured[c][k];
    throw Error("experiments/paper-claims.toml has no value " + id + " (" + label + ")");
  }
  // Claim `id`'s value `label`: its mean over the scenes, and on one scene.
  double avg(const std::string& id, const std::string& label) const { return measure(id, label).mean; }
  double at(const std::string& id, const std::string& label, const std::string& scene) const {
    for (const auto& [s, resolution, x] : measure(id, label).per)
      if (s == scene) return x;
    return std::nan("");
  }
  std::vector<double> at_each(const std::string& id, const std::string& label) const {
    return each([&](const std::string& s) { return at(id, label, s); });
  }
  // "k of n": the scenes a check of claim `id`'s `part` held on.
  std::string scenes_met(const std::string& id, const std::string& part) const {
    const size_t c = claim_index(id);
    for (size_t k = 0; k < paper_claims()[c].checks.size(); ++k)
      if (paper_claims()[c].checks[k].part == part) return fmt::format("{} of {}", verdicts[c][k].met, verdicts[c][k].of);
    throw Error("experiments/paper-claims.toml has no check of " + id + " (" + part + ")");
  }
  // Whether the checks of claim `id`'s `part` hold (claims.h, judge_claims).
  bool holds(const std::string& id, const std::string& part = "") {
    const size_t c = claim_index(id);
    const PartVerdict v = part_verdict(paper_claims()[c], verdicts[c], part);
    if (!v.any) throw Error("experiments/paper-claims.toml has no check of " + id + (part.empty() ? "" : " (" + part + ")"));
    judged.insert({id, part});
    return v.holds;
  }

  // Per-scene values of f, and their geometric mean.
  std::vector<double> each(const std::function<double(const std::string&)>& f) const {
    std::vector<double> v;
    for (const auto& s : r.scenes) v.push_back(f(s));
    return v;
  }
  double mean(const std::function<double(const std::string&)>& f) const { return F.mean(f); }
  int count(const std::function<bool(const std::string&)>& f) const {
    int n = 0;
    for (const auto& s : r.scenes) n += f(s) ? 1 : 0;
    return n;
  }
  std::string of_n(int k) const { return fmt::format("{} of {}", k, r.scenes.size()); }
  double lat(const std::string& s, const std::string& scheme, const std::string& variant = "") const {
    const SchemeResult* x = r.find(s, res(), scheme, variant);
    return x ? x->frame_latency_s : std::nan("");
  }
  const SchemeResult& get(const std::string& s, const std::string& scheme, const std::string& variant = "") const {
    const SchemeResult* x = r.find(s, res(), scheme, variant);
    if (!x) throw Error("paper: no run of " + scheme + " on " + s + (variant.empty() ? "" : " with " + variant));
    return *x;
  }
  double sp(const std::string& s, const std::string& a, const std::string& b = "baseline") const {
    return F.speedup(s, res(), a, "", b);
  }
  double thr(const std::string& s, const std::string& a, const std::string& b) const {
    return get(s, a).throughput_fps / get(s, b).throughput_fps;
  }
  double tr(const std::string& s, const std::string& a, const std::string& b = "baseline") const {
    return F.traffic(s, res(), a, b);
  }
  double cat_share(const std::string& s, const std::string& scheme, Category c) const {
    const SchemeResult& x = get(s, scheme);
    return x.total_inter_gpm_bytes() ? double(x.inter_gpm_bytes[size_t(c)]) / double(x.total_inter_gpm_bytes()) : 0;
  }
  // The baseline's colour and depth bytes between GPMs per frame.
  double framebuffer_bytes(const std::string& s) const {
    const SchemeResult& b = get(s, "baseline");
    return double(b.inter_gpm_bytes[size_t(Category::colour)] + b.inter_gpm_bytes[size_t(Category::depth)]);
  }
  // Seconds a GPM's front end spends on one draw in a run.
  static double draw_seconds(const SchemeResult& x) {
    const auto it = x.config.find("gpm.draw_cycles");
    return (it == x.config.end() ? 0 : std::stod(it->second.value)) / x.frequency_hz;
  }
  // The share of a scheme's frame its front ends spend on draws, on average
  // per GPM (draws received per frame and GPM x gpm.draw_cycles).
  double front(const std::string& s, const std::string& scheme) const {
    const SchemeResult& x = get(s, scheme);
    const double per_gpm = double(x.draws) / double(o.frames) / double(x.gpms);
    return per_gpm * draw_seconds(x) / x.frame_latency_s;
  }
  double busiest_share(const std::string& s, const std::string& scheme) const {
    const SchemeResult& x = get(s, scheme);
    double sum = 0, mx = 0;
    for (double b : x.gpm_busy_s) {
      sum += b;
      mx = std::max(mx, b);
    }
    return sum > 0 ? mx / sum : 0;
  }

  void row(const std::string& id, const std::string& what, const std::string& paper, const std::string& mean_text,
           const std::function<std::string(const std::string&)>& cell) {
    out += "| " + id + " | " + what + " | " + paper + " | " + mean_text + " |";
    for (const auto& s : r.scenes) out += fmt::format(" {} |", cell(s));
    out += "\n";
  }
  void table_head(const std::string& first, const std::string& extra) {
    out += "| " + first + " |" + extra;
    for (const auto& s : r.scenes) out += " `" + s + "` |";
    out += "\n|";
    const size_t cols = 1 + size_t(std::count(extra.begin(), extra.end(), '|')) + r.scenes.size();
    for (size_t k = 0; k < cols; ++k) out += " --- |";
    out += "\n";
  }

  void header() {
    out += "# oovr against the paper\n\n";
    out +=
        "The OO-VR paper characterises the existing ways of splitting VR rendering over a NUMA multi-GPU system\n"
        "(its Section 4) and evaluates OO-VR against them (Section 6). Its quantitative claims, " +
        paper_claims().front().id + "-" + paper_claims().back().id +
        ", are\n"
        "the rows of the first table, with the paper's values. This page puts oovr's value for each beside the\n"
        "paper's, per scene, shows how each moved with the model's changes, and explains where they differ.\n"
        "The model was not tuned to the paper's numbers: what is calibrated is calibrated against a real GPU\n"
        "([validation.md](validation.md)).\n\n";
    out += fmt::format("Generated by `{}` in {:.0f} s. ", o.command.empty() ? "oovr paper" : o.command, r.seconds);
    out += fmt::format(
        "Every scheme is measured on frames {} to {} of each camera path (AFR has them in flight, one per GPM;\n"
        "the others render them in turn, after an unmeasured warm-up pass over the same frames), on the\n"
        "paper's Table 1 machine (`configs/paper-table1.toml`)",
        o.first_frame, o.first_frame + o.frames - 1);
    const std::vector<MachineChange> changes = machine_changes(o.machine, o.machine_sources);
    if (!changes.empty()) out += " with the changes below";
    out += ". Figures are means per frame; means over scenes are geometric. The claims are at " + res() +
           "; Figure 15 also at the paper's other resolutions.\n\n";
    if (!changes.empty()) {
      // The machine, as the database's runs record it too (each key's
      // value and source in their configuration).
      out +=
          "The machine every run started from: Table 1 with these keys changed (the runs that set a key of their own, "
          "the\nfigures' sweeps, the ablations and the model's steps, keep theirs). The paper's claims are measured on "
          "it, each\nwith only its own settings changed: a value whose label names the paper's setting of a key changed "
          "here (P1's\n\"64 GB/s\" on other links) is this machine's. Their numbers are the paper's, on its "
          "machine.\n\n| key | here | Table 1 | from |\n| --- | --- | --- | --- |\n";
      for (const MachineChange& c : changes)
        out += fmt::format("| `{}` | {} | {} | {} |\n", c.key, c.value, c.fallback, markdown_text(c.source));
      out += "\n";
    }
    out += "| scene | draws | triangles | textures | vertex share of shader work |\n| --- | --- | --- | --- | --- |\n";
    for (const auto& s : r.scenes) {
      const auto& st = r.stats.at(s);
      out += fmt::format("| `{}` | {} | {} | {} | {:.1f}% |\n", s, st.draws, st.triangles, mb(double(st.texture_bytes)),
                         st.vertex_share * 100);
    }
    if (!r.skipped.empty()) {
      out += "\nNot measured:\n";
      for (const auto& s : r.skipped) out += "- " + s + "\n";
    }
    out += "\n";
  }

  // A claims table row of claim `id` from its measured values: `text`
  // writes the cell from a value lookup (the mean, or one scene's).
  void claim_row(const std::string& id, const std::string& what,
                 const std::function<std::string(const std::function<double(const std::string&)>&)>& text) {
    tabled.insert(id);
    row(id, what, paper_claim(id).words, text([&](const std::string& label) { return avg(id, label); }),
        [&](const std::string& s) { return text([&](const std::string& label) { return at(id, label, s); }); });
  }

  void claims() {
    out += "## The claims\n\n";
    out +=
        "Speed-ups are single-frame latencies against the baseline (P2 and P12: throughput); traffic is\n"
        "inter-GPM bytes per frame.\n\n";
    table_head("claim", " what | paper | mean |");
    using V = std::function<double(const std::string&)>;
    claim_row("P1", "baseline frame rate against 1 TB/s links",
              [](const V& v) { return fmt::format("{}, {}, {}", pct(v("128 GB/s")), pct(v("64 GB/s")), pct(v("32 GB/s"))); });
    claim_row("P2", "AFR throughput", [](const V& v) { return times(v("AFR throughput")); });
    claim_row("P3", "AFR single-frame latency", [](const V& v) { return pct(v("AFR latency")); });
    claim_row("P4", "tile SFR speed-up, vertical and horizontal",
              [](const V& v) { return fmt::format("V {}, H {}", pct(v("sfr-v")), pct(v("sfr-h"))); });
    claim_row("P5", "tile SFR traffic", [](const V& v) { return fmt::format("V {}, H {}", pct(v("sfr-v")), pct(v("sfr-h"))); });
    claim_row("P6", "object-level SFR speed-up (over baseline; over SFR-V, SFR-H)", [](const V& v) {
      return fmt::format("{} ({}, {})", pct(v("object")), pct(v("object over sfr-v")), pct(v("object over sfr-h")));
    });
    claim_row("P7", "object-level SFR traffic", [](const V& v) { return pct(v("object")); });
    // P8's mean is object-level SFR's alone; each scene also gives the baseline's.
    tabled.insert("P8");
    row("P8", "object-level best-to-worst GPM time (baseline's)", paper_claim("P8").words,
        fmt::format("{:.2f}", avg("P8", "object best-to-worst")), [&](const std::string& s) {
          return fmt::format("{:.2f} ({:.2f})", at("P8", "object best-to-worst", s), at("P8", "baseline best-to-worst", s));
        });
    claim_row("P9", "OO_APP speed-up over baseline, object-level, 1 TB/s", [](const V& v) {
      return fmt::format("{}, {}, {}", pct(v("oo-app")), pct(v("oo-app over object")), pct(v("oo-app over baseline-1tb")));
    });
    claim_row("P10", "OO-VR speed-up over baseline, object-level, OO_APP", [](const V& v) {
      return fmt::format("{}, {}, {}", times(v("oo-vr")), pct(v("oo-vr over object")), pct(v("oo-vr over oo-app")));
    });
    claim_row("P11", "OO-VR traffic against baseline, object-level",
              [](const V& v) { return fmt::format("{}, {}", pct(v("oo-vr")), pct(v("oo-vr over object"))); });
    // Energy beside the traffic it follows (Section 6.2 argues it; model.md, "Energy").
    claim_row("P18", "energy against baseline: OO-VR's links, object-level's links; OO-VR's memory system", [](const V& v) {
      return fmt::format("{}, {}; {}", pct(v("oo-vr links")), pct(v("object links")), pct(v("oo-vr memory")));
    });
    claim_row("P12", "OO-VR throughput against AFR; AFR latency against OO-VR", [](const V& v) {
      return fmt::format("{}; {}", times(v("oo-vr throughput over afr")), pct(v("afr latency over oo-vr")));
    });
    claim_row("P13", "speed-up from 32 GB/s to 1 TB/s links: OO-VR (baseline, object-level)",
              [](const V& v) { return fmt::format("{} ({}, {})", pct(v("oo-vr")), pct(v("baseline")), pct(v("object"))); });
    claim_row("P14", "speed-up over 1 GPM at 8 GPMs: baseline, object-level, OO-VR (OO-VR at 4)", [](const V& v) {
      return fmt::format("{}, {}, {} ({})", times(v("baseline, 8 GPMs")), times(v("object, 8 GPMs")), times(v("oo-vr, 8 GPMs")),
                         times(v("oo-vr, 4 GPMs")));
    });
    claim_row("P15", "SMP against two sequential views (one GPM)", [](const V& v) { return pct(v("SMP")); });
    const OOSpec spec = o.spec.own<OOSettings>("oo").parameters;
    const int gpms = o.spec.memory.gpms;
    const EngineStorage st = engine_storage(gpms, spec.batch_queue);
    tabled.insert("P16");
    row("P16", "distribution engine storage", paper_claim("P16").words, fmt::format("{} bits", st.total()),
        [&](const std::string&) { return fmt::format("{} bits", st.total()); });
    // Claims the document has no words of its own for: each value's mean,
    // as the claims file writes it.
    for (const Claim& c : paper_claims()) {
      if (tabled.count(c.id)) continue;
      claim_row(c.id, c.what, [&](const V& v) {
        std::string t;
        for (const ClaimValue& x : c.values) t += (t.empty() ? "" : ", ") + in_form(x, v(x.label));
        return t;
      });
    }
    out += fmt::format(
        "\nP16 is computed from the configuration ({} GPMs, a queue of {}): two 64-bit counters per GPM ({} bits),\n"
        "a 16-bit id per queued batch ({}), and three 32-bit registers per GPM for the current batch's triangles,\n"
        "transformed vertices and pixels ({}).\n\n",
        gpms, spec.batch_queue, st.counter_bits, st.batch_id_bits, st.register_bits);
  }

  void check(const std::string& id, const std::string& what, const std::function<std::string(const std::string&)>& cell) {
    out += "| " + id + " | " + what + " |";
    for (const auto& sc : r.scenes) out += fmt::format(" {} |", cell(sc));
    out += "\n";
  }

  void checks() {
    out += "### Checks of the explanations\n\nEach row measures a cause the explanations below name.\n\n";
    table_head("check", " what |");
    check("X1", "baseline remote texture bytes per frame",
          [&](const std::string& s) { return mb(double(get(s, "baseline").inter_gpm_bytes[size_t(Category::texture)])); });
    check("X2", "composition bytes per frame: object-level, OO_APP, OO-VR", [&](const std::string& s) {
      return fmt::format("{}, {}, {}", mb(double(get(s, "object").inter_gpm_bytes[size_t(Category::composition)])),
                         mb(double(get(s, "oo-app").inter_gpm_bytes[size_t(Category::composition)])),
                         mb(double(get(s, "oo-vr").inter_gpm_bytes[size_t(Category::composition)])));
    });
    check("X3", "busiest GPM's share of all GPM busy time: object-level, OO_APP, OO-VR (25% is even)", [&](const std::string& s) {
      return fmt::format("{:.0f}%, {:.0f}%, {:.0f}%", busiest_share(s, "object") * 100, busiest_share(s, "oo-app") * 100,
                         busiest_share(s, "oo-vr") * 100);
    });
    check("X4", "OO-VR pre-allocation bytes per frame",
          [&](const std::string& s) { return mb(double(get(s, "oo-vr").inter_gpm_bytes[size_t(Category::prealloc)])); });
    check("X5", "data resident in GPM memories: baseline, OO-VR, AFR", [&](const std::string& s) {
      return fmt::format("{}, {}, {}", mb(double(get(s, "baseline").footprint_bytes)),
                         mb(double(get(s, "oo-vr").footprint_bytes)), mb(double(get(s, "afr").footprint_bytes)));
    });
    check("X6", "the baseline's speed-up over one GPM (4x if NUMA cost nothing)",
          [&](const std::string& s) { return times(1 / sp(s, "single-gpm")); });
    check("X7", "object-level SFR and OO-VR against the baseline, all with 1 TB/s links", [&](const std::string& s) {
      const double b = lat(s, "baseline", "link.bandwidth=1TBps");
      return fmt::format("{}, {}", times(b / lat(s, "object", "link.bandwidth=1TBps")),
                         times(b / lat(s, "oo-vr", "link.bandwidth=1TBps")));
    });
    check("X8", "OO-VR batches per frame (mean triangles)", [&](const std::string& s) {
      for (const auto& n : get(s, "oo-vr").notes)
        if (n.find(" batches of ") != std::string::npos) return n.substr(0, n.find(';'));
      return std::string("n/a");
    });
    check("X9", "front-end time per GPM over the frame (gpm.draw_cycles per draw received): baseline, object-level, OO-VR",
          [&](const std::string& s) {
            return fmt::format("{:.0f}%, {:.0f}%, {:.0f}%", front(s, "baseline") * 100, front(s, "object") * 100,
                               front(s, "oo-vr") * 100);
          });
    check("X10", "the baseline's colour and depth bytes between GPMs per frame (an eye's GPMs share its framebuffer pages)",
          [&](const std::string& s) { return mb(framebuffer_bytes(s)); });
    out += "\n";
  }

  // --- The model's steps (issue 9): each claim's mean, step by step. ---

  struct StepClaim {
    std::string id, text;
    double value;  // the main ratio, for spotting what moved
  };

  // The claims' means under one step of the model (paper_figures.h), over
  // `scenes` (every scene when null); with `one_pass`, over those scenes'
  // one-pass workloads instead.
  std::vector<StepClaim> step_claims(const ModelStep& st, const std::vector<std::string>* scenes = nullptr,
                                     bool one_pass = false) const {
    const std::string& b = st.baseline;
    const auto V = [&](const std::string& extra) {
      if (!one_pass) return step_variant(st, extra);
      return extra.empty() ? kOnePassVariant : kOnePassVariant + ";" + extra;
    };
    const auto N = [&](const std::string& s) { return one_pass ? one_pass_scene(s) : s; };
    const auto L = [&](const std::string& s, const std::string& scheme, const std::string& extra = "") {
      return lat(N(s), scheme, V(extra));
    };
    const auto T = [&](const std::string& s, const std::string& scheme) {
      const SchemeResult* x = r.find(N(s), res(), scheme, V(""));
      return x ? x->throughput_fps : std::nan("");
    };
    const auto B = [&](const std::string& s, const std::string& scheme) {
      const SchemeResult* x = r.find(N(s), res(), scheme, V(""));
      return x ? double(x->total_inter_gpm_bytes()) : std::nan("");
    };
    const auto M = [&](const std::function<double(const std::string&)>& f) {
      if (!scenes) return mean(f);
      std::vector<double> v;
      for (const auto& sc : *scenes)
        if (const double x = f(sc); std::isfinite(x) && x > 0) v.push_back(x);
      return geomean(v);
    };
    const auto sp_ = [&](const std::string& scheme) { return M([&](auto& s) { return L(s, b) / L(s, scheme); }); };
    const auto tr_ = [&](const std::string& scheme) {
      return M([&](auto& s) { return B(s, b) > 0 ? B(s, scheme) / B(s, b) : std::nan(""); });
    };
    std::vector<StepClaim> c;
    const double p1 = M([&](auto& s) { return L(s, b, "link.bandwidth=1TBps") / L(s, b); });
    c.push_back({"P1", pct(p1), p1});
    const double p2 = M([&](auto& s) { return T(s, "afr") / T(s, b); });
    c.push_back({"P2", times(p2), p2});
    const double p3 = 1 / sp_("afr");
    c.push_back({"P3", pct(p3), p3});
    c.push_back({"P4", "V " + pct(sp_("sfr-v")) + ", H " + pct(sp_("sfr-h")), sp_("sfr-v")});
    c.push_back({"P5", "V " + pct(tr_("sfr-v")) + ", H " + pct(tr_("sfr-h")), tr_("sfr-v")});
    c.push_back({"P6", pct(sp_("object")), sp_("object")});
    c.push_back({"P7", pct(tr_("object")), tr_("object")});
    const double p8 = M([&](auto& s) {
      const SchemeResult* x = r.find(N(s), res(), "object", V(""));
      return x ? x->best_to_worst() : std::nan("");
    });
    c.push_back({"P8", fmt::format("{:.2f}", p8), p8});
    c.push_back({"P9", pct(sp_("oo-app")), sp_("oo-app")});
    const double vr_app = M([&](auto& s) { return L(s, "oo-app") / L(s, "oo-vr"); });
    c.push_back({"P10", times(sp_("oo-vr")) + ", " + pct(vr_app), sp_("oo-vr")});
    c.push_back({"P11", pct(tr_("oo-vr")), tr_("oo-vr")});
    const double p12 = M([&](auto& s) { return T(s, "oo-vr") / T(s, "afr"); });
    c.push_back({"P12", times(p12) + "; " + pct(M([&](auto& s) { return L(s, "afr") / L(s, "oo-vr"); })), p12});
    const double p13 = M([&](auto& s) { return L(s, "oo-vr", "link.bandwidth=32GBps") / L(s, "oo-vr", "link.bandwidth=1TBps"); });
    c.push_back({"P13",
                 pct(p13) + " (" +
                     pct(M([&](auto& s) { return L(s, b, "link.bandwidth=32GBps") / L(s, b, "link.bandwidth=1TBps"); })) + ")",
                 p13});
    const auto at8 = [&](const std::string& scheme) {
      return M([&](auto& s) { return L(s, "single-gpm") / L(s, scheme, "gpms=8"); });
    };
    c.push_back({"P14", times(at8(b)) + ", " + times(at8("object")) + ", " + times(at8("oo-vr")), at8("oo-vr")});
    const double p15 = M([&](auto& s) { return L(s, "two-pass") / L(s, "single-gpm"); });
    c.push_back({"P15", pct(p15), p15});
    return c;
  }

  // The main ratio of a ca88d23 text ("-12%" is 0.88, "1.54x" 1.54).
  static double first_value(const std::string& text) {
    size_t i = text.find_first_of("+-0123456789");
    if (i == std::string::npos) return std::nan("");
    size_t end = i + 1;
    while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.')) ++end;
    const double v = std::stod(text.substr(i, end - i));
    return end < text.size() && text[end] == '%' ? 1 + v / 100 : v;
  }

  // The claims' values under two workloads, side by side, with the main
  // ratio's change where it exceeds 10%; returns those claims' ids.
  std::string claims_side_by_side(const std::vector<StepClaim>& a, const std::vector<StepClaim>& b, const std::string& a_name,
                                  const std::string& b_name) {
    out += "| claim | paper | " + a_name + " | " + b_name + " | moved |\n| --- | --- | --- | --- | --- |\n";
    std::string list;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
      const double x = a[i].value, y = b[i].value;
      const bool m = x > 0 && y > 0 && std::abs(std::log(y / x)) > std::log(1.1);
      if (m) list += (list.empty() ? "" : ", ") + a[i].id;
      out += fmt::format("| {} | {} | {} | {} | {} |\n", a[i].id, paper_claim(a[i].id).short_form, a[i].text, b[i].text,
                         m ? times(y / x) : "");
    }
    return list;
  }

  // A captured game (trace:, oa-demo:, nexuiz-demo:): what it drew, frame by frame.
  static bool captured_scene(const std::string& s) {
    return s.rfind("oa-demo:", 0) == 0 || s.rfind("nexuiz-demo:", 0) == 0 || s.rfind("trace:", 0) == 0;
  }

  // Real game frames against the levels (issue 27): the statistics the
  // explanations rely on and the claims, as means over each kind.
  void real_frames() {
    std::vector<std::string> captured, levels;
    for (const auto& s : r.scenes) (captured_scene(s) ? captured : levels).push_back(s);
    if (captured.empty() || levels.empty()) return;
    out += "## Real game frames against the levels\n\n";
    out +=
        "The levels are oovr's own camera walks through static maps; a captured game is what the game sent to its GPU,\n"
        "frame by frame: players, weapon, particles, sky, flares and HUD ([real-frames.md](real-frames.md)). The\n"
        "explanations below lean on how much a workload draws and moves; this section sets the statistics they rely on\n"
        "and the claims, as means over each kind of workload, side by side (arithmetic means of the statistics,\n"
        "geometric of the ratios).\n\n";
    const auto avg = [](const std::vector<std::string>& sc, const std::function<double(const std::string&)>& f) {
      double sum = 0;
      for (const auto& s : sc) sum += f(s);
      return sc.empty() ? 0.0 : sum / double(sc.size());
    };
    const auto tex = [&](const std::string& s) { return double(get(s, "baseline").inter_gpm_bytes[size_t(Category::texture)]); };
    const auto batches = [&](const std::string& s) { return scheme_metric(get(s, "oo-vr"), "batches"); };
    const auto draws = [&](const std::string& s) { return double(r.stats.at(s).draws); };
    const auto tris = [&](const std::string& s) { return double(r.stats.at(s).triangles); };
    const double d_lv = avg(levels, draws), d_cap = avg(captured, draws);
    const double t_lv = avg(levels, tex), t_cap = avg(captured, tex);
    const double f_lv = avg(levels, [&](auto&s) { return front(s, "baseline"); }),
                 f_cap = avg(captured, [&](auto&s) { return front(s, "baseline"); });
    const double b_lv = avg(levels, batches), b_cap = avg(captured, batches);
    std::string names;
    for (const auto& s : captured) names += (names.empty() ? "`" : ", `") + s + "`";
    out += "| statistic | levels (" + std::to_string(levels.size()) + ") | real frames (" + names + ") |\n| --- | --- | --- |\n";
    out += fmt::format("| draws in the first frame measured | {:.0f} | {:.0f} |\n", d_lv, d_cap);
    out += fmt::format("| triangles in it | {:.0f} | {:.0f} |\n", avg(levels, tris), avg(captured, tris));
    out += fmt::format("| X1: baseline remote texture bytes per frame | {} | {} |\n", mb(t_lv), mb(t_cap));
    out += fmt::format("| X9: baseline front-end time over the frame | {:.0f}% | {:.0f}% |\n", f_lv * 100, f_cap * 100);
    out += fmt::format("| X8: OO-VR batches per frame | {:.1f} | {:.1f} |\n", b_lv, b_cap);
    const auto x6 = [&](const std::vector<std::string>& sc) {
      std::vector<double> v;
      for (const auto& s : sc) v.push_back(1 / sp(s, "single-gpm"));
      return times(paper::geomean(v));
    };
    out += fmt::format("| X6: the baseline over one GPM | {} | {} |\n", x6(levels), x6(captured));
    const ModelStep& now = kSteps.back();
    const auto lv = step_claims(now, &levels, false), cap = step_claims(now, &captured, false);
    out += "\nThe claims' means over each kind (forms as in the before-and-after table):\n\n";
    const std::string list = claims_side_by_side(lv, cap, "levels", "real frames");
    out +=
        fmt::format("\n\"moved\" gives the main ratio's change from the levels to the real frames where it exceeds 10% ({}).\n\n",
                    list.empty() ? "none" : list);
    // What the real frames say of the explanations, from the figures above.
    const auto ratio = [](double a, double b) { return b > 0 ? a / b : std::nan(""); };
    const double more_draws = ratio(d_cap, d_lv), more_tex = ratio(t_cap, t_lv);
    out += "What the real frames say of the explanations below:\n\n";
    out += fmt::format(
        "- *Draws.* The real frames issue {:.0f} draws a frame, {} the levels' {:.0f} (the paper's games: 191 to 1,697). "
        "The baseline's front ends spend {:.0f}% of its frame on them against {:.0f}% on the levels (X9): {}\n",
        d_cap, times(more_draws), d_lv, f_cap * 100, f_lv * 100,
        f_cap >= f_lv * 0.9 ? "the per-draw cost of broadcasting every draw, the first explanation, holds on what a game draws."
        : f_cap >= 0.5
            ? "the first explanation, the per-draw cost of broadcasting every draw, holds on what a game draws, less strongly "
              "than on the levels, which draw every surface group of their map in every frame where a game draws what its "
              "visibility test keeps."
            : "on what a game draws the per-draw cost weighs less than on the levels (which draw every surface group of their "
              "map in every frame), so the first explanation accounts for less of the differences there.");
    out += fmt::format(
        "- *Data moved.* The baseline fetches {} of remote texture data a frame on the real frames, {} on the levels "
        "(X1): {}\n",
        mb(t_cap), mb(t_lv),
        more_tex > 2 ? "the levels' camera walks did move less data than a game's frames, as the second explanation says."
        : more_tex < 0.5
            ? "a game's frames move even less than the levels. What the camera walks leave out (players, weapon, particles, "
              "HUD) is not why oovr's scenes move less data than the paper's: the second explanation holds, but its cause is "
              "the workload's textures themselves, not the walks."
            : "about as much as the levels. What the camera walks leave out (players, weapon, particles, HUD) is not why "
              "oovr's scenes move less data than the paper's: the second explanation holds, but its cause is the workload's "
              "textures themselves, not the walks.");
    out += fmt::format(
        "- *Batches.* OO-VR makes {:.1f} batches a frame of the real frames and {:.1f} of the levels (X8); the real "
        "frames' 2-D overlay and a shader's stages must keep their order, which the middleware honours by keeping them "
        "in one batch.\n\n",
        b_cap, b_lv);
  }

  // One-pass workloads against real-material ones (issue 10): the same
  // game levels, the claims on each.
  void workloads() {
    const auto& games = r.one_pass_scenes;
    out += "## Workloads: one pass against real materials\n\n";
    out += fmt::format(
        "oovr's game levels used to be drawn with one opaque pass per surface group (its shader's first image times its\n"
        "lightmap), textures stored as RGBA8 and every fragment costing 32 instructions. They are now drawn as their engines\n"
        "draw them: OpenArena's shaders pass by pass as ioquake3, Nexuiz's surfaces lit per pixel as DarkPlaces (diffuse,\n"
        "normal, gloss, glow, lightmap and deluxe maps in one pass), block-compressed storage, and each pass costing what it\n"
        "samples and computes ([workloads.md](workloads.md), [model.md](model.md)). This section runs the same {} levels\n"
        "both ways at {} (`{}` with `{}` and `{}`: the one-pass workloads) and sets the claims' means side by side.\n\n",
        games.size(), res(), kOnePassOption, kOnePassWindow, kOnePassVariant);
    // What the change does to the work, per level, and its span over the
    // levels (frame time and remote texture bytes, for the prose below).
    std::vector<double> frame, texture;
    out +=
        "| scene | baseline frame time, real / one pass | baseline texture bytes from other GPMs, real / one pass "
        "| baseline inter-GPM bytes, real / one pass |\n| --- | --- | --- | --- |\n";
    for (const auto& sc : games) {
      const SchemeResult* a = r.find(one_pass_scene(sc), res(), "baseline", kOnePassVariant);
      const SchemeResult* b = r.find(sc, res(), "baseline");
      if (!a || !b) continue;
      const double ta = double(a->inter_gpm_bytes[size_t(Category::texture)]),
                   tb = double(b->inter_gpm_bytes[size_t(Category::texture)]);
      frame.push_back(b->frame_latency_s / a->frame_latency_s);
      if (ta > 0) texture.push_back(tb / ta);
      out += fmt::format(
          "| `{}` | {} | {} | {} |\n", sc, times(frame.back()), ta > 0 ? times(tb / ta) : "n/a",
          a->total_inter_gpm_bytes() ? times(double(b->total_inter_gpm_bytes()) / double(a->total_inter_gpm_bytes())) : "n/a");
    }
    const ModelStep& now = kSteps.back();
    const auto one = step_claims(now, &games, true), real = step_claims(now, &games, false);
    out += "\nThe claims' means over these levels (forms as in the before-and-after table):\n\n";
    const std::string list = claims_side_by_side(one, real, "one-pass workloads", "real materials");
    const auto span = [](std::vector<double> v) {
      if (v.empty()) return std::string("n/a");
      std::sort(v.begin(), v.end());
      return times(v.front()) + " to " + times(v.back());
    };
    out += fmt::format(
        "\n\"moved\" gives the main ratio's change where it exceeds 10% ({}).\n\n"
        "Why they move. The real materials add work of two kinds, and the per-level table gives the size of each on the\n"
        "baseline. Shading work grows: more passes per surface on OpenArena, 100 to 150 instructions per lit Nexuiz\n"
        "fragment, 2 to 5 texture layers per shaded fragment where the one-pass levels sampled 2; the baseline's frames\n"
        "take {} as long. Texture bytes move the other way: block compression stores a texel in an eighth (BC1) or a\n"
        "quarter (BC3) of RGBA8's bytes, which outweighs the extra layers, so the texture bytes the baseline's GPMs fetch\n"
        "from each other change by {}. With less remote texture traffic, schemes that keep an object's textures local\n"
        "(object-level SFR, OO-VR's batching and pre-allocation) have less to save against the baseline, and what they\n"
        "add themselves (composition, pre-allocated copies, their imbalance) weighs more: the claims on their traffic and\n"
        "speed-up (P6 to P12) follow from that balance. Longer shaders make every scheme more compute-bound, which\n"
        "changes how schemes that split frames scale with GPMs (P14) and what AFR gains in throughput (P2, P3). The paper's\n"
        "games also compressed their textures, so the real-material column is the closer one to its setting; its remaining\n"
        "gaps are explained in the sections below.\n\n",
        list.empty() ? "none" : list, span(frame), span(texture));
  }

  void before_after() {
    out += "## Before and after: the model's changes, claim by claim\n\n";
    out += "The claims' means (" + res() +
           ") as the model changed (issue 9): `ca88d23` is the document as it was generated\n"
           "before; each later column switches on one change on top of those to its left, through the configuration keys\n"
           "that keep the older behaviour (the settings are listed below the table); the last column is the model as it\n"
           "is, the `mean` column above. The forms are those of the claims table, shortened: P1 at 64 GB/s; P6 and P9\n"
           "against the baseline; P10 against the baseline and OO_APP; P13 OO-VR (the baseline); P14 at 8 GPMs, for the\n"
           "baseline, object-level SFR and OO-VR. Every claim is measured against the column's baseline.\n\n";
    std::vector<std::vector<StepClaim>> steps;
    for (const auto& st : kSteps) steps.push_back(step_claims(st));
    out += "| claim | paper | ca88d23 |";
    for (const auto& st : kSteps) out += " " + st.label + " |";
    out += "\n| --- | --- | --- |";
    for (size_t k = 0; k < kSteps.size(); ++k) out += " --- |";
    out += "\n";

    for (size_t i = 0; i < steps.front().size(); ++i) {
      const std::string& id = steps.front()[i].id;
      const std::string& was = paper_claim(id).before;
      const std::string before = was.empty() ? "n/a" : was;
      out += "| " + id + " | " + paper_claim(id).short_form + " | " + before + " |";
      for (const auto& st : steps) out += " " + st[i].text + " |";
      out += "\n";
    }
    out += "\nWhat each step changes, and the claims it moved most (their main ratio by more than 10%):\n\n";
    for (size_t k = 0; k < kSteps.size(); ++k) {
      std::vector<std::pair<double, std::string>> moved;
      for (size_t i = 0; i < steps[k].size(); ++i) {
        double from = std::nan("");
        std::string from_text;
        if (k == 0) {
          from_text = paper_claim(steps[k][i].id).before;
          if (!from_text.empty()) from = first_value(from_text);
        } else {
          from = steps[k - 1][i].value;
          from_text = steps[k - 1][i].text;
        }
        const double to = steps[k][i].value;
        if (!(from > 0 && to > 0)) continue;
        const double change = std::abs(std::log(to / from));
        if (change > std::log(1.1)) moved.push_back({change, steps[k][i].id + " " + from_text + " to " + steps[k][i].text});
      }
      std::sort(moved.begin(), moved.end(), [](const auto& a, const auto& b2) { return a.first > b2.first; });
      std::string list;
      for (const auto& m : moved) list += (list.empty() ? "" : "; ") + m.second;
      const std::string settings =
          kSteps[k].settings.empty() ? std::string("the configuration as it is") : fmt::format("`{}`", kSteps[k].settings);
      const std::string what = list.empty() ? std::string("No claim moved by more than 10%.") : fmt::format("Moved: {}.", list);
      out += fmt::format("- **{}** ({}): {}. {}\n", kSteps[k].label, settings, kSteps[k].change, what);
    }
    out += '\n';
    out += step_reasons();
    out += '\n';
  }

  // A configuration value in force (as the runs resolved it).
  std::string setting(const std::string& key) const {
    const SchemeResult& x = get(r.scenes.front(), "baseline");
    const auto it = x.config.find(key);
    return it == x.config.end() ? "n/a" : it->second.value;
  }

  // The scene with the most draws: what its draws cost each broadcast GPM.
  std::string most_draws() const {
    std::string scene;
    size_t draws = 0;
    for (const auto& sc : r.scenes)
      if (r.stats.at(sc).draws > draws) {
        draws = r.stats.at(sc).draws;
        scene = sc;
      }
    if (scene.empty()) return "";
    const SchemeResult& b = get(scene, "baseline");
    const double front = double(draws) * draw_seconds(b);
    return fmt::format(
        "On `{}` ({} draws) the front end of every GPM of the baseline is busy {:.0f} us per frame, "
        "{:.0f}% of the baseline's frame.",
        scene, draws, front * 1e6, front / b.frame_latency_s * 100);
  }

  // Why the steps moved the claims: each step's mechanism with its measured
  // size (means over scenes at the sweep resolution).
  std::string step_reasons() const {
    const auto run = [&](size_t k, const std::string& s, const std::string& scheme, const std::string& extra = "") {
      return r.find(s, res(), scheme, step_variant(kSteps[k], extra));
    };
    const auto bytes = [&](size_t k, const std::string& scheme, int c = -1) {
      return geomean(F.across([&](const std::string& s) {
        const SchemeResult* x = run(k, s, scheme);
        if (!x) return std::nan("");
        return c < 0 ? double(x->total_inter_gpm_bytes()) : double(x->inter_gpm_bytes[size_t(c)]);
      }));
    };
    const auto latency = [&](size_t k, const std::string& scheme, const std::string& extra = "") {
      return geomean(F.across([&](const std::string& s) {
        const SchemeResult* x = run(k, s, scheme, extra);
        return x ? x->frame_latency_s : std::nan("");
      }));
    };
    const auto vs = [](double after, double before) { return pct(after / before); };
    std::string t = "Why (geometric means over the scenes):\n\n";
    t += fmt::format(
        "- *defects fixed*: two-pass issues and transforms every draw in each view, as single-gpm transforms every "
        "draw once (two-pass takes {} of single-gpm's time here); OO_APP deals its batches without the hardware queue; "
        "set-up triangles handed to another GPM wait for the link latency; the page deal is even; remote caches set to "
        "be invalidated per draw now are (not the default, so no claim depends on it).\n",
        times(latency(0, "two-pass") / latency(0, "single-gpm")));
    t += fmt::format(
        "- *paper's baseline*: dealt tile by tile, the GPMs of an eye share its colour and depth pages: the baseline moves "
        "{} MB between GPMs per frame against the page deal's {} MB (colour and depth {} MB), and is {} slower. "
        "Every traffic ratio falls with the larger denominator and every speed-up rises with the slower baseline.\n",
        fmt::format("{:.1f}", bytes(1, "baseline") / 1e6), fmt::format("{:.1f}", bytes(0, "baseline-paged") / 1e6),
        fmt::format("{:.1f}", (bytes(1, "baseline", int(Category::colour)) + bytes(1, "baseline", int(Category::depth))) / 1e6),
        vs(latency(1, "baseline"), latency(0, "baseline-paged")));
    t += fmt::format(
        "- *colour composition*: object-level SFR's composition goes from {} to {} MB per frame, but its depth tests now "
        "read and write the root's depth buffer across the links ({} MB of depth); its frame changes by {}, OO-VR's by {}.\n",
        fmt::format("{:.1f}", bytes(2 - 1, "object", int(Category::composition)) / 1e6),
        fmt::format("{:.1f}", bytes(2, "object", int(Category::composition)) / 1e6),
        fmt::format("{:.1f}", bytes(2, "object", int(Category::depth)) / 1e6), vs(latency(2, "object"), latency(1, "object")),
        vs(latency(2, "oo-vr"), latency(1, "oo-vr")));
    t += fmt::format(
        "- *fair sharing*: a unit that cannot use its share of a link, a DRAM or the ROPs leaves it to the others instead "
        "of wasting it. The baseline changes by {}, object-level SFR by {} (its root's ROPs compose beside its own "
        "rendering), OO-VR by {}.\n",
        vs(latency(3, "baseline"), latency(2, "baseline")), vs(latency(3, "object"), latency(2, "object")),
        vs(latency(3, "oo-vr"), latency(2, "oo-vr")));
    t += fmt::format(
        "- *reads in flight*: every read holds a request slot for its latency (a remote one crosses the links twice), so a "
        "GPM whose reads miss often, or go far, waits. One GPM changes by {}, the baseline by {}; at 32 GB/s links the "
        "baseline changes by {} against 1 TB/s (from {}).\n",
        vs(latency(4, "single-gpm"), latency(3, "single-gpm")), vs(latency(4, "baseline"), latency(3, "baseline")),
        vs(latency(4, "baseline", "link.bandwidth=32GBps") / latency(4, "baseline", "link.bandwidth=1TBps"), 1.0),
        vs(latency(3, "baseline", "link.bandwidth=32GBps") / latency(3, "baseline", "link.bandwidth=1TBps"), 1.0));
    t += fmt::format(
        "- *per-draw front end*: every GPM that receives a draw spends gpm.draw_cycles on it. The baseline and tile SFR "
        "broadcast every draw to every GPM, so their front ends do the whole frame's draws each, however many GPMs there "
        "are; object-level SFR, OO_APP and OO-VR send each draw to one GPM. One GPM changes by {}, the baseline by {}, "
        "object-level SFR by {}, OO-VR by {}. {}\n",
        vs(latency(5, "single-gpm"), latency(4, "single-gpm")), vs(latency(5, "baseline"), latency(4, "baseline")),
        vs(latency(5, "object"), latency(4, "object")), vs(latency(5, "oo-vr"), latency(4, "oo-vr")), most_draws());
    return t;
  }

  void figure15() {
    out += "## Figure 15: speed-up of every scheme\n\nSingle-frame latency against the baseline, per scene and resolution.\n\n";
    const std::vector<std::string> shown = {"baseline-1tb", "afr", "sfr-v", "sfr-h", "object", "oo-app", "oo-vr", "ideal"};
    out += "| scene | resolution |";
    for (const auto& s : shown) out += fmt::format(" {} |", s);
    out += "\n| --- | --- |";
    for (size_t k = 0; k < shown.size(); ++k) out += " --- |";
    out += "\n";
    for (const auto& resolution : o.resolutions) {
      for (const auto& s : r.scenes) {
        if (!r.find(s, resolution, "baseline")) continue;
        out += "| `" + s + "` | " + resolution + " |";
        for (const auto& sc : shown) out += fmt::format(" {} |", times(F.speedup(s, resolution, sc)));
        out += "\n";
      }
      out += "| geomean | " + resolution + " |";
      for (const auto& sc : shown)
        out += fmt::format(" {} |", times(F.mean([&](const std::string& s) { return F.speedup(s, resolution, sc); })));
      out += "\n";
    }
    if (!plots.empty()) out += "\n![Figure 15](" + plots + "/fig15-speedup.svg)\n";
    out += "\n";
  }

  void figure16() {
    out += "## Figure 16: inter-GPM traffic\n\nBytes per frame at " + res() + ", and the ratio to the baseline's.\n\n";
    const std::vector<std::string> shown = {"sfr-v", "sfr-h", "object", "oo-app", "oo-vr"};
    out += "| scene | baseline |";
    for (const auto& s : shown) out += fmt::format(" {} |", s);
    out += " OO-VR's bytes by category |\n| --- | --- |";
    for (size_t k = 0; k <= shown.size(); ++k) out += " --- |";
    out += "\n";
    for (const auto& s : r.scenes) {
      out += "| `" + s + "` | " + mb(double(get(s, "baseline").total_inter_gpm_bytes())) + " |";
      for (const auto& sc : shown) out += fmt::format(" {} |", times(tr(s, sc)));
      std::string cats;
      const SchemeResult& x = get(s, "oo-vr");
      for (int c = 0; c < kCategories; ++c)
        if (x.inter_gpm_bytes[size_t(c)] >= 10000)
          cats += (cats.empty() ? "" : ", ") + std::string(category_name(Category(c))) + " " +
                  mb(double(x.inter_gpm_bytes[size_t(c)]));
      out += " " + cats + " |\n";
    }
    if (!plots.empty()) out += "\n![Figure 16](" + plots + "/fig16-traffic.svg)\n";
    out += "\n";
    energy();
  }

  // A scheme's memory-system energy per frame on scene `s`.
  Energy energy(const std::string& s, const std::string& scheme) const { return energy_of(get(s, scheme)); }
  // The links' price per bit: the machine's, one for all links.
  double link_price() const { return o.spec.memory.link_energy_per_bit.value; }
  // A run's energy with its links priced between nodes (250 pJ/bit): link
  // energy is linear in its price, so this is the run's own links scaled.
  double between_nodes(const Energy& x) const { return x.total() - x.links + x.links * 250e-12 / link_price(); }

  // The energy the traffic above costs (P18): the memory system's per
  // frame, by part, and the same runs with links between nodes (the 250
  // pJ/bit columns: between_nodes, not another run).
  void energy() {
    const double price = link_price();
    out += fmt::format(
        "### Energy (P18)\n\nThe memory system's energy per frame at {} (caches, DRAM and links at {:g} pJ/bit; "
        "[model.md](model.md#energy)), and the\nratio to the baseline's; the last columns price the same links at "
        "250 pJ/bit, between nodes.\n\n",
        res(), price * 1e12);
    out +=
        "| scene | baseline | its links | object | oo-vr | oo-vr's links | oo-vr's DRAM | baseline, 250 pJ/bit | oo-vr, 250 "
        "pJ/bit |\n";
    out += "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    const auto mj = [](double j) { return fmt::format("{:.2f} mJ", j * 1e3); };
    std::vector<double> total, links, nodes;
    for (const auto& s : r.scenes) {
      const Energy b = energy(s, "baseline"), ob = energy(s, "object"), oo = energy(s, "oo-vr");
      out += "| `" + s + "` | " + mj(b.total()) + " | " + mj(b.links) + " | " + times(ob.total() / b.total()) + " | " +
             times(oo.total() / b.total()) + " | " + times(oo.links / b.links) + " | " + times(oo.dram / b.dram) + " | " +
             mj(between_nodes(b)) + " | " + times(between_nodes(oo) / between_nodes(b)) + " |\n";
      total.push_back(oo.total() / b.total());
      links.push_back(oo.links / b.links);
      nodes.push_back(between_nodes(oo) / between_nodes(b));
    }
    out += fmt::format(
        "\nOver the scenes (geometric mean) OO-VR's links take {} of the baseline's energy and its memory system {};\n"
        "with links between nodes, {}. Where OO-VR moves fewer bytes between GPMs its links save in proportion, but its\n"
        "pre-allocated copies are DRAM writes, so on a board the memory system saves less than the links do.\n\n",
        times(geomean(links)), times(geomean(total)), times(geomean(nodes)));
  }

  void figure17() {
    out += "## Figure 17: link bandwidth\n\nSpeed-up against the baseline with " + machine_value(o, "link.bandwidth") +
           " links (geometric mean over scenes).\n\n";
    out += "| link | baseline | object | oo-vr |\n| --- | --- | --- | --- |\n";
    for (const auto& link : kLinks) {
      // (Clang 14 cannot capture structured bindings in lambdas.)
      const std::string& bw = link.first;
      const double gbps = link.second;
      out += fmt::format("| {} |", gbps >= 1000 ? std::string("1 TB/s") : fmt::format("{:.0f} GB/s", gbps));
      for (const auto& sc : kSweepSchemes) out += fmt::format(" {} |", times(mean([&](auto& s) { return F.link(s, sc, bw); })));
      out += "\n";
    }
    if (!plots.empty()) out += "\n![Figure 17](" + plots + "/fig17-links.svg)\n";
    out += "\n";
  }

  void figure18() {
    out += "## Figure 18: number of GPMs\n\nSpeed-up against one GPM (geometric mean over scenes).\n\n";
    out += "| GPMs | baseline | object | oo-vr |\n| --- | --- | --- | --- |\n";
    for (int n : kGpms) {
      out += fmt::format("| {} |", n);
      for (const auto& sc : kSweepSchemes) out += fmt::format(" {} |", times(mean([&](auto& s) { return F.gpms(s, sc, n); })));
      out += "\n";
    }
    if (!plots.empty()) out += "\n![Figure 18](" + plots + "/fig18-gpms.svg)\n";
    out += "\n";
  }

  void ablations() {
    out += "## OO-VR's mechanisms\n\n";
    out += "Speed-up against the baseline at " + res() +
           " with each mechanism added to OO_APP, and taken out of OO-VR (`--set oo.<switch>=...`).\n\n";
    table_head("variant", " mean |");
    const auto line = [&](const std::string& label, const std::string& scheme, const std::string& variant) {
      out += "| " + label + " | " + times(mean([&](auto& s) { return F.speedup(s, res(), scheme, variant); })) + " |";
      for (const auto& s : r.scenes) out += fmt::format(" {} |", times(F.speedup(s, res(), scheme, variant)));
      out += "\n";
    };
    line("oo-app", "oo-app", "");
    for (const auto& [label, key] : kMechanisms) line("oo-app + " + label, "oo-app", key + "=" + on_value(key));
    line("oo-vr", "oo-vr", "");
    for (const auto& [label, key] : kMechanisms) line("oo-vr - " + label, "oo-vr", key + "=" + off_value(key));
    // Shares of the gain from OO_APP to OO-VR: the log of what taking each
    // mechanism out of OO-VR costs, over the log of OO-VR's gain.
    const double gain = mean([&](auto& s) { return lat(s, "oo-app") / lat(s, "oo-vr"); });
    out += fmt::format(
        "\nFrom OO_APP to OO-VR the frame gets {} faster (geometric mean). Taking one mechanism out of OO-VR costs:\n\n",
        times(gain));
    for (const auto& mechanism : kMechanisms) {
      const std::string& label = mechanism.first;
      const std::string& key = mechanism.second;
      const double loss = mean([&](auto& s) { return lat(s, "oo-vr", key + "=" + off_value(key)) / lat(s, "oo-vr"); });
      const double share = std::log(gain) != 0 ? std::log(loss) / std::log(gain) : std::nan("");
      out += fmt::format("- {}: {} ({:.0f}% of the gain, in log terms)\n", label, pct(loss), share * 100);
    }
    out +=
        "\nThe shares need not add up to 100%: the mechanisms interact (pre-allocation only pays when the predictor\n"
        "sends batches ahead of time; the split needs GPMs left idle by the distribution).\n\n";
  }

  // OO-VR's copies against the memory they may take (Section 5.2: the
  // pre-allocation units copy "to the corresponding unused DRAM"): capped
  // per GPM (kCopyCapacities), and uncapped in the DRAM (the main runs).
  void copies() {
    const std::vector<std::pair<std::string, double>> points = copy_points(F.dram_bytes());
    out += "## OO-VR's copies and the memory they live in\n\n";
    out += fmt::format(
        "OO-VR's pre-allocation units copy a batch's data into the GPM that will render it, and the split copies the\n"
        "data of the work it moves, \"to the corresponding unused DRAM\" (Section 5.2). The paper gives no capacity. In\n"
        "oovr copies live in what a GPM's homes (the buffers, textures and framebuffers placed there) leave of its DRAM,\n"
        "`dram.capacity` = {} per GPM (NVIDIA's GTX 1080, the GPU the paper's GPM resembles, has 8 GB), persist from\n"
        "frame to frame while they fit, and the least recently used give way when they do not. `memory.copies.capacity`\n"
        "caps them further; this section caps them at 16 MB to 1 GB per GPM at {} and sets OO-VR's speed-up and\n"
        "traffic against the baseline (which makes no copies) beside the {} runs. \"held\" is the most one GPM held\n"
        "{}: where the scene's copies fit.\n\n",
        setting("dram.capacity"), res(),
        F.copies_capped() ? "machine's own (capped at " + setting("memory.copies.capacity") + ")" : "uncapped",
        F.copies_capped() ? "in them" : "uncapped");
    out += "| scene | held |";
    for (const auto& [cap, bytes] : points)
      out += fmt::format(" {}{} |", format_bytes(Bytes{uint64_t(bytes)}),
                         !cap.empty()        ? ""
                         : F.copies_capped() ? " (the machine's)"
                                             : " (DRAM)");
    out += "\n| --- | --- |";
    for (size_t k = 0; k < points.size(); ++k) out += " --- |";
    out += "\n";
    std::vector<double> held;
    for (const auto& s : r.scenes) {
      const SchemeResult* x = r.find(s, res(), "oo-vr");
      held.push_back(x ? scheme_metric(*x, "copies.peak_bytes") : std::nan(""));
      out += "| `" + s + "` | " + (std::isfinite(held.back()) ? mb(held.back()) : "n/a") + " |";
      for (const auto& point : points)
        out += fmt::format(" {}, {} |", times(F.copies_speedup(s, point.first)), times(F.copies_traffic(s, point.first)));
      out += "\n";
    }
    out += "| geomean | |";
    for (const auto& point : points)
      out += fmt::format(" {}, {} |", times(mean([&](auto& s) { return F.copies_speedup(s, point.first); })),
                         times(mean([&](auto& s) { return F.copies_traffic(s, point.first); })));
    out += "\n\nEach cell: speed-up, then inter-GPM traffic, against the baseline.\n";
    if (!plots.empty()) out += "\n![OO-VR against copy capacity](" + plots + "/copies.svg)\n";
    // Where a cap bites: the scenes whose copies outgrow 16 MB, and what
    // pre-allocation moves there with and without it.
    const std::string& small = kCopyCapacities.front().first;
    std::string over;
    int n_over = 0;
    for (size_t i = 0; i < r.scenes.size(); ++i)
      if (std::isfinite(held[i]) && held[i] > kCopyCapacities.front().second) {
        over += (over.empty() ? "`" : ", `") + r.scenes[i] + "`";
        ++n_over;
      }
    const auto prealloc = [&](const std::string& variant) {
      return mean([&](auto& s) {
        const SchemeResult* x = r.find(s, res(), "oo-vr", variant);
        return x ? double(x->inter_gpm_bytes[size_t(Category::prealloc)]) : std::nan("");
      });
    };
    if (n_over == 0) out += "\nEvery scene's copies fit in 16 MB per GPM here, so no cap changes anything.";
    else
      out += fmt::format(
          "\nThe copies of {} outgrow 16 MB per GPM:\n{}.\nCapped there, a batch's copies are dropped before the batch "
          "comes back in the next frame, so pre-allocation\ncopies the same data frame after frame: {} of copies per "
          "frame (geometric mean over the scenes) against\n{} uncapped, and OO-VR's mean speed-up is {} against {}.",
          of_n(n_over), over, mb(prealloc(copy_variant(small))), mb(prealloc("")),
          times(mean([&](auto& s) { return F.copies_speedup(s, small); })),
          times(mean([&](auto& s) { return F.copies_speedup(s, ""); })));
    out += fmt::format(
        " oovr's model had such a cap (16 MB,\nassumed) as its \"bounded copies\" step until the copies moved into the "
        "DRAM; the before-and-after table no\nlonger has that step, since in {} of DRAM every scene's copies fit.\n\n",
        setting("dram.capacity"));
  }

  // "lo to hi" of plain shares (0.31 -> "31%") and of megabytes.
  std::string shares(const std::vector<double>& v) const {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *lo == *hi ? fmt::format("{:.0f}%", *lo * 100) : fmt::format("{:.0f}% to {:.0f}%", *lo * 100, *hi * 100);
  }
  std::string mbs(const std::vector<double>& v) const {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *lo == *hi ? mb(*lo) : fmt::format("{:.1f} to {:.1f} MB", *lo / 1e6, *hi / 1e6);
  }
  std::vector<double> cat_bytes(const std::string& scheme, Category c) const {
    return each([&](const std::string& s) { return double(get(s, scheme).inter_gpm_bytes[size_t(c)]); });
  }
  std::vector<double> busiest(const std::string& scheme) const {
    return each([&](const std::string& s) { return busiest_share(s, scheme); });
  }

  // Bytes per frame a scheme moves between GPMs (mean over scenes).
  double moved(const std::string& scheme, const std::string& variant = "") const {
    return mean([&](const std::string& s) {
      const SchemeResult* x = r.find(s, res(), scheme, variant);
      return x ? double(x->total_inter_gpm_bytes()) : std::nan("");
    });
  }
  // Seconds the links need for `bytes` at `gbps` each, spread evenly over
  // every link of the machine (a lower bound of the time they take).
  double link_seconds(const std::string& s, double bytes, double gbps) const {
    const SchemeResult& b = get(s, "baseline");
    const int n = b.gpms;
    return bytes / (double(n * (n - 1)) * gbps * 1e9);
  }

  void agree_and_differ() {
    std::vector<std::string> agree, differ;
    const auto claim = [&](bool ok, const std::string& text) { (ok ? agree : differ).push_back(text); };
    const double x6 = mean([&](auto& s) { return 1 / sp(s, "single-gpm"); });
    const auto fronts = [&](const std::string& scheme) { return each([&](const std::string& s) { return front(s, scheme); }); };
    // The claims without per-draw cost: the steps table's column before the
    // front end (the last step's predecessor), when it was run.
    const ModelStep& no_front = kSteps[kSteps.size() - 2];
    const auto step_sp = [&](const ModelStep& st, const std::string& scheme, const std::string& against = "baseline") {
      return mean([&](auto& s) { return lat(s, against, step_variant(st, "")) / lat(s, scheme, step_variant(st, "")); });
    };
    const bool have_steps = o.steps && r.find(r.scenes.front(), res(), "baseline", step_variant(no_front, ""));

    // P1
    const auto loss = [&](const std::string& bw) {
      return (1 -
              mean([&](auto& s) { return lat(s, "baseline", "link.bandwidth=1TBps") / lat(s, "baseline", link_variant(bw)); })) *
             100;
    };
    claim(holds("P1", "direction"),
          fmt::format("**P1, direction.** The baseline gets faster with every step up in link bandwidth on {} scenes.",
                      scenes_met("P1", "direction")));
    // For the paper's loss at 64 GB/s, the frame at 64 GB/s would be the
    // 1 TB/s frame over the paper's ratio, with the links busy all of it:
    // the bytes that takes.
    const double needed = mean([&](auto& s) {
      const double t = lat(s, "baseline", "link.bandwidth=1TBps") / paper("P1", "64 GB/s");
      return t / link_seconds(s, double(get(s, "baseline").total_inter_gpm_bytes()), 64);
    });
    claim(
        holds("P1", "magnitude"),
        fmt::format(
            "**P1, magnitude.** At 64 GB/s the baseline loses {:.0f}% of its 1 TB/s frame rate (the paper: {:.0f}%), "
            "at 32 GB/s {:.0f}% (the paper: {:.0f}%). Two things hold it back. Its front ends: every GPM receives every draw, "
            "and draws are {} of its frame (X9), a time no link speeds up{}. And its bytes: {} MB between GPMs per "
            "frame (textures {}, X1; colour and depth {}, X10). For the paper's {:.0f}% the links would have to be "
            "busy for the whole of a frame {:.1f}x the 1 TB/s one: about {:.1f}x the bytes the baseline moves here, "
            "even spread over all links.",
            loss("64GBps"), paper_loss("P1", "64 GB/s"), loss("32GBps"), paper_loss("P1", "32 GB/s"), shares(fronts("baseline")),
            have_steps ? fmt::format(" (without the per-draw cost it loses {:.0f}%)",
                                     (1 - mean([&](auto& s) {
                                        return lat(s, "baseline", step_variant(no_front, "link.bandwidth=1TBps")) /
                                               lat(s, "baseline", step_variant(no_front, ""));
                                      })) *
                                         100)
                       : "",
            fmt::format("{:.1f}", moved("baseline") / 1e6), mbs(cat_bytes("baseline", Category::texture)),
            mbs(each([&](auto& s) { return framebuffer_bytes(s); })), paper_loss("P1", "64 GB/s"), 1 / paper("P1", "64 GB/s"),
            needed));
    // P2, P3
    const bool afr_faster = holds("P2", "direction"), afr_slower = holds("P3", "direction");  // both judged
    claim(afr_faster && afr_slower,
          fmt::format("**P2, P3, direction.** AFR's throughput beats the baseline's on {} scenes ({}; the paper {}) and its "
                      "single frame is slower on {} ({}): each frame has one GPM, a quarter of the machine.",
                      scenes_met("P2", "direction"), range(at_each("P2", "AFR throughput"), false),
                      paper_text("P2", "AFR throughput"), scenes_met("P3", "direction"),
                      range(at_each("P3", "AFR latency"), true)));
    const double afr_thr = avg("P2", "AFR throughput");
    claim(holds("P2", "magnitude"),
          fmt::format("**P2, magnitude.** AFR's throughput is {} the baseline's (the paper {}). Each AFR GPM receives only its "
                      "own frame's draws, while the baseline's four front ends each receive every draw: where the draws "
                      "dominate (X9) AFR's advantage approaches 4x. For the paper's {} the baseline's front ends would have to "
                      "matter little{}.",
                      times(afr_thr), paper_text("P2", "AFR throughput"), paper_text("P2", "AFR throughput"),
                      have_steps ? fmt::format(" (without the per-draw cost AFR's throughput is {})", times(mean([&](auto& s) {
                                                 const SchemeResult* a = r.find(s, res(), "afr", step_variant(no_front, ""));
                                                 const SchemeResult* b = r.find(s, res(), "baseline", step_variant(no_front, ""));
                                                 return a && b ? a->throughput_fps / b->throughput_fps : std::nan("");
                                               })))
                                 : ""));
    claim(holds("P3", "magnitude"),
          fmt::format("**P3, magnitude.** AFR's single frame takes {} longer than the baseline's (the paper: {}): one GPM "
                      "renders it, against four GPMs that are {} faster than one here (X6).",
                      pct(avg("P3", "AFR latency")), paper_text("P3", "AFR latency"), times(x6)));
    // P4
    claim(
        holds("P4"),
        fmt::format("**P4.** Vertical strips beat the baseline on {} scenes ({}; the paper {}) and beat horizontal strips on {} "
                    "(horizontal strips against the baseline: {}; the paper {}). Horizontal strips are as uneven as the work is "
                    "from top to bottom: upper strips are often sky. Both broadcast every draw, as the baseline does, so on "
                    "scenes bound by their front ends (X9) neither gains.",
                    of_n(count([&](auto& s) { return at("P4", "sfr-v", s) > 1; })), range(at_each("P4", "sfr-v"), true),
                    paper_text("P4", "sfr-v"), of_n(count([&](auto& s) { return at("P4", "sfr-v", s) > at("P4", "sfr-h", s); })),
                    range(at_each("P4", "sfr-h"), true), paper_text("P4", "sfr-h")));
    // P5
    claim(
        holds("P5"),
        fmt::format("**P5.** Against the baseline, vertical strips change the bytes between GPMs by {} (the paper {}), "
                    "horizontal strips by {} ({}). The paper's baseline deals its tiles without regard to pages, so the GPMs "
                    "of an eye share its colour and depth ({} per frame, X10), which strips do not; against the page-aware "
                    "baseline (`baseline-paged`, whose framebuffer stays local) vertical strips move {} and horizontal ones {}. "
                    "For the paper's {}, strips would have to repeat far more than the texture data they cut through: the "
                    "paper's scenes have larger objects spanning strips (its Figure 6 bridge). Horizontal strips span both eyes, "
                    "so SMP keeps both views' data in one GPM.",
                    range(at_each("P5", "sfr-v"), true), paper_text("P5", "sfr-v"), range(at_each("P5", "sfr-h"), true),
                    paper_text("P5", "sfr-h"), mbs(each([&](auto& s) { return framebuffer_bytes(s); })),
                    pct(mean([&](auto& s) { return tr(s, "sfr-v", "baseline-paged"); })),
                    pct(mean([&](auto& s) { return tr(s, "sfr-h", "baseline-paged"); })), paper_text("P5", "sfr-v")));
    // P6-P8
    const bool object_faster = holds("P6", "direction"), object_less = holds("P7", "direction");  // both judged
    claim(object_faster && object_less,
          fmt::format("**P6, P7, direction.** Object-level SFR beats the baseline on {} scenes ({}; mean {}, the paper {}) and "
                      "changes the "
                      "bytes between GPMs by {} (mean {}, the paper {}). Each draw goes to one GPM (X9: its front ends {} of "
                      "its frame, the baseline's {}), its colour goes to the root ({} per frame, X2), and its depth tests read "
                      "and write the root's depth buffer. Round-robin gives the busiest GPM {} of all busy time (X3): where a "
                      "few objects carry most pixels (the courtyard) it still loses. The paper's {} would need the imbalance "
                      "of X3 to be small on every scene.",
                      scenes_met("P6", "direction"), range(at_each("P6", "object"), true), pct(avg("P6", "object")),
                      paper_text("P6", "object"), range(at_each("P7", "object"), true), pct(avg("P7", "object")),
                      paper_text("P7", "object"), shares(fronts("object")), shares(fronts("baseline")),
                      mbs(cat_bytes("object", Category::composition)), shares(busiest("object")), paper_text("P6", "object")));
    claim(holds("P8"),
          fmt::format("**P8.** Round-robin objects leave the GPMs more unbalanced than the baseline on {} scenes (best-to-worst "
                      "{}): a few objects (floor, sky, large brushes) carry most pixels, and the root also composes.",
                      scenes_met("P8", ""), range(at_each("P8", "object best-to-worst"), false)));
    // P9
    claim(
        holds("P9"),
        fmt::format("**P9.** OO_APP is {} against the baseline (mean {}, the paper {}) and {} against object-level SFR (mean {}, "
                    "the paper {}). Batching by texture sharing keeps texture reads local and each object's two views are one "
                    "draw, but the scenes' draws make few, large batches (X8), and round-robin over them is uneven: the busiest "
                    "GPM has {} of all busy time (X3). The paper saw the same on Doom 3 (object-level SFR beat OO_APP there); "
                    "its {} would need batches even enough for round-robin to balance.",
                    range(at_each("P9", "oo-app"), true), pct(avg("P9", "oo-app")), paper_text("P9", "oo-app"),
                    range(at_each("P9", "oo-app over object"), true), pct(avg("P9", "oo-app over object")),
                    paper_text("P9", "oo-app over object"), shares(busiest("oo-app")), paper_text("P9", "oo-app")));
    // P10
    claim(holds("P10"),
          fmt::format("**P10.** OO-VR is {} the baseline's speed (mean {}, the paper {}), {} against object-level SFR ({}) and "
                      "{} against OO_APP ({}). The engine evens out the GPMs (busiest GPM {} of busy time, X3), each draw goes "
                      "to one GPM, and DHC spreads composition over every GPM's ROPs; what remains is composition ({}, X2) and "
                      "the copies pre-allocation makes as batches move between GPMs from frame to frame ({}, X4), kept in "
                      "the GPMs' DRAM ({} each; resident data, X5).",
                      range(at_each("P10", "oo-vr"), false), times(avg("P10", "oo-vr")), paper_text("P10", "oo-vr"),
                      range(at_each("P10", "oo-vr over object"), true), paper_text("P10", "oo-vr over object"),
                      range(at_each("P10", "oo-vr over oo-app"), true), paper_text("P10", "oo-vr over oo-app"),
                      shares(busiest("oo-vr")), mbs(cat_bytes("oo-vr", Category::composition)),
                      mbs(cat_bytes("oo-vr", Category::prealloc)), setting("dram.capacity")));
    // P11
    claim(
        holds("P11"),
        fmt::format("**P11.** OO-VR changes the bytes between GPMs by {} against the baseline (mean {}, the paper {}) and by {} "
                    "against object-level SFR ({}). Its remote texture reads are gone, but DHC ships the colour of every line "
                    "a GPM writes outside its own strip, about (N-1)/N of all written lines ({}, X2), its depth tests cross to "
                    "the strips' owners, and copies follow the batches ({}, X4). For the paper's {} these would have to come "
                    "to {:.0f}% of the baseline's bytes ({} MB per frame here, against OO-VR's {} MB).",
                    range(at_each("P11", "oo-vr"), true), pct(avg("P11", "oo-vr")), paper_text("P11", "oo-vr"),
                    range(at_each("P11", "oo-vr over object"), true), paper_text("P11", "oo-vr over object"),
                    mbs(cat_bytes("oo-vr", Category::composition)), mbs(cat_bytes("oo-vr", Category::prealloc)),
                    paper_text("P11", "oo-vr"), paper("P11", "oo-vr") * 100, fmt::format("{:.1f}", moved("baseline") / 1e6),
                    fmt::format("{:.1f}", moved("oo-vr") / 1e6)));
    // P12
    claim(holds("P12"),
          fmt::format("**P12.** OO-VR's throughput is {} of AFR's (the paper: similar), and AFR's single frame is {} slower than "
                      "OO-VR's (the paper: {}). AFR's frames in flight keep every GPM busy with no traffic at all, each GPM "
                      "receiving a quarter of the draws; OO-VR also divides the draws but pays composition ({}, X2) and its "
                      "imbalance (X3) within each frame. For similar throughput OO-VR's frame would have to be within "
                      "20% of a quarter of AFR's.",
                      range(at_each("P12", "oo-vr throughput over afr"), false),
                      range(at_each("P12", "afr latency over oo-vr"), true), paper_text("P12", "afr latency over oo-vr"),
                      mbs(cat_bytes("oo-vr", Category::composition))));
    // P13
    const auto spread = [&](const std::string& scheme) {
      return mean([&](auto& s) { return F.link(s, scheme, "1TBps") / F.link(s, scheme, "32GBps"); });
    };
    const bool flat = holds("P13");
    claim(flat,
          fmt::format("**P13.** From 32 GB/s to 1 TB/s links OO-VR gains {}, the baseline {} and object-level SFR {} (the "
                      "paper: {}). {}",
                      pct(spread("oo-vr")), pct(spread("baseline")), pct(spread("object")), paper_claim("P13").words,
                      flat ? "OO-VR keeps its data local; what it still moves, composition, DHC spreads over all links."
                           : fmt::format("OO-VR no longer reads textures remotely, but what it moves instead, composition "
                                         "({}, X2), copies ({}, X4) and depth tests in other GPMs' strips, comes to {} MB per "
                                         "frame against the baseline's {} MB, so it needs the links about as much; and the "
                                         "baseline is partly bound by its front ends (X9), which no link speeds up. For a "
                                         "nearly flat OO-VR its bytes between GPMs would have to be a small fraction of the "
                                         "baseline's (the paper's {}, P11).",
                                         mbs(cat_bytes("oo-vr", Category::composition)),
                                         mbs(cat_bytes("oo-vr", Category::prealloc)), fmt::format("{:.1f}", moved("oo-vr") / 1e6),
                                         fmt::format("{:.1f}", moved("baseline") / 1e6), paper_text("P11", "oo-vr"))));
    // P14
    const auto at = [&](const std::string& scheme, int g) { return mean([&](auto& s) { return F.gpms(s, scheme, g); }); };
    const bool order = holds("P14", "direction"), near = holds("P14", "magnitude");
    claim(order && near,
          fmt::format(
              "**P14.** Over one GPM, at 8 GPMs OO-VR reaches {}, object-level SFR {} and the baseline {} (the paper "
              "{}, {}, {}); at 4 GPMs OO-VR {} ({}); at 16 GPMs {}, {} and {}. {}",
              times(at("oo-vr", 8)), times(at("object", 8)), times(at("baseline", 8)), paper_text("P14", "oo-vr, 8 GPMs"),
              paper_text("P14", "object, 8 GPMs"), paper_text("P14", "baseline, 8 GPMs"), times(at("oo-vr", 4)),
              paper_text("P14", "oo-vr, 4 GPMs"), times(at("oo-vr", 16)), times(at("object", 16)), times(at("baseline", 16)),
              order ? fmt::format("The order is the paper's: the baseline's front ends receive every draw whatever the "
                                  "number of GPMs (X9), object-level SFR's busiest GPM sets its time (X3), OO-VR "
                                  "divides the draws and balances. OO-VR's 8 GPMs stay below the paper's {}: "
                                  "on the smaller scenes its batches are few for 8 GPMs (X8), and its composition "
                                  "and copies cross more links.",
                                  paper_text("P14", "oo-vr, 8 GPMs"))
                    : "The order differs from the paper's; X3, X6 and X9 show how balanced each scheme is, what NUMA costs "
                      "the baseline and how much its front ends bind it."));
    // P15
    double vs_lo = 1, vs_hi = 0;
    for (const auto& s : r.scenes) {
      vs_lo = std::min(vs_lo, r.stats.at(s).vertex_share);
      vs_hi = std::max(vs_hi, r.stats.at(s).vertex_share);
    }
    const double smp = avg("P15", "SMP");
    claim(holds("P15"),
          fmt::format("**P15.** SMP is {} against rendering the two views in sequence (mean {}, the paper {}). Two passes issue "
                      "every draw twice and transform its vertices twice; vertex shading is {:.1f}% to {:.1f}% of these scenes' "
                      "shader work (the table at the top), so most of the difference is the second draw's front-end cost, "
                      "largest on the scenes with many draws{}. For the paper's {} the second pass would have to cost about a "
                      "quarter of a frame: more than the courtyard's few large draws do, less than forza's thousands.",
                      range(at_each("P15", "SMP"), true), pct(smp), paper_text("P15", "SMP"), vs_lo * 100, vs_hi * 100,
                      have_steps ? fmt::format(" (without the per-draw cost SMP gains {})",
                                               pct(step_sp(no_front, "single-gpm", "two-pass")))
                                 : "",
                      paper_text("P15", "SMP")));
    {
      const EngineStorage st = engine_storage(o.spec.memory.gpms, o.spec.own<OOSettings>("oo").parameters.batch_queue);
      claim(holds("P16"),
            fmt::format("**P16.** The engine's storage, computed from the configuration, is {} bits (the paper: {}).", st.total(),
                        paper_text("P16", "engine storage")));
    }

    // P18
    {
      const double dram = mean([&](auto& s) { return energy(s, "oo-vr").dram / energy(s, "baseline").dram; });
      const double nodes =
          mean([&](auto& s) { return between_nodes(energy(s, "oo-vr")) / between_nodes(energy(s, "baseline")); });
      claim(holds("P18"),
            fmt::format("**P18.** At {:g} pJ/bit OO-VR's links change their energy by {} against the baseline's (mean {}) "
                        "and its memory system's by {} (mean {}; the paper: {}, with no number). The links' energy follows their "
                        "bytes (P11): where OO-VR "
                        "moves fewer, they save in proportion. Its pre-allocated copies are DRAM writes, so its DRAMs take "
                        "{} of the baseline's energy, and its composition and depth tests in other GPMs' strips cross the "
                        "links ({}, X2). Priced between nodes (250 pJ/bit) the links dominate and OO-VR's memory system takes "
                        "{} of the baseline's. For the paper's saving OO-VR would have to move fewer bytes than the baseline "
                        "(P11). oovr prices the moving of data only ([model.md](model.md#energy)), not the SMs' arithmetic, "
                        "which differs between the schemes only where they transform vertices more than once.",
                        link_price() * 1e12, range(at_each("P18", "oo-vr links"), true), pct(avg("P18", "oo-vr links")),
                        range(at_each("P18", "oo-vr memory"), true), pct(avg("P18", "oo-vr memory")), paper_claim("P18").words,
                        times(dram), mbs(cat_bytes("oo-vr", Category::composition)), times(nodes)));
    }

    // Claims (or parts) the prose above has no words for: what the claims
    // file says of them, oovr's means and each check's verdict.
    for (const Claim& c : paper_claims()) {
      std::vector<std::string> parts;
      for (const ClaimCheck& k : c.checks)
        if (std::find(parts.begin(), parts.end(), k.part) == parts.end()) parts.push_back(k.part);
      for (const std::string& part : parts) {
        if (judged.count({c.id, part})) continue;
        std::string values, checked;
        for (const ClaimValue& v : c.values) {
          const std::vector<double> x = at_each(c.id, v.label);
          values += fmt::format("{}{} {} ({})", values.empty() ? "" : "; ", v.label, in_form(v, avg(c.id, v.label)),
                                v.form == "percent" ? range(x, true)
                                : v.form == "times" ? range(x, false)
                                                    : "per scene");
        }
        const size_t ci = claim_index(c.id);
        for (size_t k = 0; k < c.checks.size(); ++k)
          if (c.checks[k].part == part)
            checked += fmt::format(
                "{}{}{}", checked.empty() ? "" : "; ", c.checks[k].says,
                c.checks[k].over == "mean" ? "" : fmt::format(" (on {} of {} scenes)", verdicts[ci][k].met, verdicts[ci][k].of));
        claim(holds(c.id, part), fmt::format("**{}{}.** {} (the paper: {}). oovr: {}. Checked: {}.", c.id,
                                             part.empty() ? "" : ", " + part, c.what, c.words, values, checked));
      }
    }

    out += "## Where oovr agrees\n\n";
    for (const auto& a : agree) out += "- " + a + "\n";
    out += "\n## Where oovr differs, and why\n\n";
    out += fmt::format(
        "Two causes lie behind most differences. **Draws cost every GPM that receives them.** The per-draw front-end cost "
        "is calibrated on a real GPU (gpm.draw_cycles, [validation.md](validation.md)); the baseline and tile SFR broadcast "
        "every draw to every GPM, so on scenes with many draws their front ends take {} of their frame (X9) and more GPMs or "
        "faster links do not help, while object-level SFR, OO_APP, OO-VR and AFR divide the draws. The paper does not say "
        "what a draw cost its GPMs. **These scenes move less data than the paper's.** The baseline's remote texture traffic is "
        "{} per frame (X1), where the paper's Doom 3 and Half-Life 2 traces fetch tens of MB; four GPMs are {} faster than "
        "one (X6; 4x if NUMA cost nothing). What sort-last schemes pay instead, composition, does not shrink with the "
        "textures (X2). The steps table above shows each claim with and without each part of the model.\n\n",
        shares(fronts("baseline")), mbs(cat_bytes("baseline", Category::texture)), times(x6));
    for (const auto& d : differ) out += "- " + d + "\n";
  }
};

}  // namespace

std::string paper::plots_link(const std::string& doc, const std::string& plots_dir) {
  if (plots_dir.empty()) return "";
  std::error_code ec;
  const fs::path doc_dir = fs::absolute(fs::path(doc)).parent_path();
  const std::string link = fs::relative(fs::absolute(plots_dir), doc_dir, ec).generic_string();
  return ec || link.empty() ? fs::absolute(plots_dir).generic_string() : link;
}

void write_paper_doc(const PaperResults& results, const PaperOptions& options, const std::string& path,
                     const std::string& plots_dir) {
  Doc d(results, options, plots_link(path, plots_dir));
  const std::string text = d.write();
  write_output_file(path, text, "comparison document");
}

namespace {

// A claim's checks as judged, in words: "direction yes, magnitude no"
// (a part holds when all of its checks do).
std::string verdict_text(const Claim& c, const std::vector<CheckVerdict>& v) {
  std::vector<std::string> parts;
  for (const ClaimCheck& k : c.checks)
    if (std::find(parts.begin(), parts.end(), k.part) == parts.end()) parts.push_back(k.part);
  std::string out;
  for (const std::string& part : parts) {
    const PartVerdict p = part_verdict(c, v, part);
    out += (out.empty() ? "" : ", ") + (part.empty() ? std::string("the claim") : part) + " " +
           (!p.measured ? "not measured"
            : p.holds   ? "yes"
                        : "no");
  }
  return out.empty() ? "no check" : out;
}

}  // namespace

Config paper_against_machine(const std::string& other_db, const std::string& sweep_name) {
  const ResultsDb db(other_db, ResultsDb::Access::read_only);
  db.verify();
  const auto definitions = db.sweep_definitions();
  const auto it = definitions.find(sweep_name);
  if (it == definitions.end()) {
    std::string held;
    for (const auto& [name, d] : definitions) held += (held.empty() ? "'" : ", '") + name + "'";
    throw Error("--against: the database '" + other_db + "' holds no sweep '" + sweep_name + "' (it holds " +
                (held.empty() ? std::string("none") : held) + ")");
  }
  try {
    return sweep_machine(parse_sweep(it->second, sweep_name, ""));
  } catch (const Error& e) {
    throw Error("--against: the machine of the sweep '" + sweep_name + "' in '" + other_db + "': " + e.what());
  }
}

void write_paper_against(const PaperResults& r, const PaperOptions& o, const std::string& other_db, const Config& other_machine,
                         const std::string& dir) {
  const std::string& res = o.sweep_resolution;
  // The other evaluation's runs of this sweep's name (its database checked
  // by paper_against_machine).
  std::vector<RunRecord> theirs;
  {
    const ResultsDb db(other_db, ResultsDb::Access::read_only);
    for (RunRecord& x : db.runs(false))
      if (x.sweep == o.sweep.name && x.status == "done" && x.resolution == res) {
        x.result = nullptr;
        theirs.push_back(std::move(x));
      }
  }
  // Like for like: the scenes both measured at the claims' resolution.
  std::vector<std::string> scenes;
  for (const std::string& scene : r.scenes)
    if (std::any_of(theirs.begin(), theirs.end(), [&](const RunRecord& x) { return x.scene == scene; })) scenes.push_back(scene);
  if (scenes.empty())
    throw Error("--against: the database '" + other_db + "' has no run at " + res + " of a scene this evaluation measured");
  const auto keep = [&](std::vector<RunRecord>& v) {
    v.erase(std::remove_if(v.begin(), v.end(),
                           [&](const RunRecord& x) {
                             return x.resolution != res || std::find(scenes.begin(), scenes.end(), x.scene) == scenes.end();
                           }),
            v.end());
  };
  std::vector<RunRecord> mine = r.records;
  keep(mine);
  keep(theirs);
  const nlohmann::ordered_json here_values = machine_values(o.machine), there_values = machine_values(other_machine);
  const auto here = measure_claims(paper_claims(), mine, &here_values);
  const auto there = measure_claims(paper_claims(), theirs, &there_values);
  const auto here_judged = judge_claims(paper_claims(), here);
  const auto there_judged = judge_claims(paper_claims(), there);

  std::string md = "# The paper's claims on two machines\n\n";
  md += fmt::format("Generated by `{}`. Each claim of the paper measured as in the comparison with the paper, on this\n",
                    markdown_text(o.command.empty() ? "oovr paper" : o.command));
  md += fmt::format(
      "evaluation's machine (\"here\") and on the machine of `{}` (\"there\"), at {} over the {} scenes both\n"
      "measured ({}); means over scenes are geometric. Each claim's value is measured on each machine with only its own\n"
      "settings changed: a value whose label names the paper's setting of a key a machine changes (P1's \"64 GB/s\" on\n"
      "other links) is that machine's. The paper's numbers are on its own machine.\n\n",
      markdown_text(other_db), res, scenes.size(), [&] {
        std::string list;
        for (const auto& x : scenes) list += (list.empty() ? "`" : ", `") + markdown_text(x) + "`";
        return list;
      }());
  // The machines: every key either changes from Table 1.
  const auto here_changes = machine_changes(o.machine, o.machine_sources);
  const auto there_changes = machine_changes(other_machine);
  std::map<std::string, std::pair<std::string, std::string>> keys;  // key -> (here, there)
  std::map<std::string, std::string> table1;
  for (const auto& c : here_changes) {
    keys[c.key].first = c.value + " (" + c.source + ")";
    table1[c.key] = c.fallback;
  }
  for (const auto& c : there_changes) {
    keys[c.key].second = c.value;
    table1[c.key] = c.fallback;
  }
  md += "## The machines\n\n";
  if (keys.empty()) {
    md += "Both are the paper's Table 1 machine.\n\n";
  } else {
    md += "The keys either machine changes from the paper's Table 1 (a blank: Table 1's value).\n\n";
    md += "| key | here | there | Table 1 |\n| --- | --- | --- | --- |\n";
    for (const auto& [key, v] : keys)
      md += fmt::format("| `{}` | {} | {} | {} |\n", key, markdown_text(v.first), markdown_text(v.second),
                        markdown_text(table1[key]));
    md += "\n";
  }
  md += "## The claims\n\n| claim | value | paper | here | there | there / here | agrees here | agrees there |\n";
  md += "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  std::string csv = "claim,value,scene,paper,here,there\n";
  const auto& claims = paper_claims();
  for (size_t c = 0; c < claims.size(); ++c) {
    const Claim& claim = claims[c];
    for (size_t k = 0; k < claim.values.size(); ++k) {
      const ClaimValue& v = claim.values[k];
      const double a = here[c][k].mean, b = there[c][k].mean;
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", k == 0 ? claim.id : "", markdown_text(v.label),
                        v.paper ? (v.about ? "about " : "") + in_form(v, *v.paper) : "", in_form(v, a), in_form(v, b),
                        std::isfinite(a) && std::isfinite(b) && a != 0 ? times(b / a) : "n/a",
                        k == 0 ? verdict_text(claim, here_judged[c]) : "", k == 0 ? verdict_text(claim, there_judged[c]) : "");
      const auto number = [](double x) { return std::isfinite(x) ? fmt::format("{:.6g}", x) : std::string("nan"); };
      for (const auto& scene : scenes) {
        double x = std::nan(""), y = std::nan("");
        for (const auto& [s, rr, value] : here[c][k].per)
          if (s == scene) x = value;
        for (const auto& [s, rr, value] : there[c][k].per)
          if (s == scene) y = value;
        csv += fmt::format("{},{},{},{},{},{}\n", claim.id, csv_field(v.label), csv_field(scene), v.paper ? number(*v.paper) : "",
                           number(x), number(y));
      }
      csv += fmt::format("{},{},geomean,{},{},{}\n", claim.id, csv_field(v.label), v.paper ? number(*v.paper) : "", number(a),
                         number(b));
    }
  }
  md +=
      "\nEach value in the claim's form (a ratio as a percentage or times, or bits); \"there / here\" is the other\n"
      "machine's value over this one's. \"agrees\": whether the claim's checks hold on that machine, as the comparison\n"
      "with the paper judges them.\n";
  const fs::path d(dir);
  write_output_file((d / "paper-against.md").string(), md, "comparison of two machines");
  write_output_file((d / "claims-against.csv").string(), csv, "comparison of two machines");
}

}  // namespace oovr
