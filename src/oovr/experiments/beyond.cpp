#include "oovr/experiments/beyond.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>

#include "oovr/core/files.h"
#include "oovr/core/text.h"
#include "oovr/core/units.h"
#include "oovr/experiments/paper_figures.h"
#include "oovr/experiments/svg_chart.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {
namespace fs = std::filesystem;
using namespace paper;

namespace embedded {
extern const char* const beyond_toml;
}

std::string beyond_sweep_text() { return embedded::beyond_toml; }
Sweep beyond_sweep() { return parse_sweep(embedded::beyond_toml, "experiments/beyond.toml", ""); }

namespace {

// The study's schemes at 4 GPMs, in the document's order, and those swept
// over GPM counts and link bandwidths.
const std::vector<std::string> kSchemes = {"baseline", "sfr-v", "sfr-h",  "sfr-lb", "object",
                                           "per-eye",  "gpupd", "chopin", "oo-vr",  "oo-vr-affinity"};
const std::vector<std::string> kSwept = {"baseline", "sfr-v",  "sfr-lb", "object",        "per-eye",
                                         "gpupd",    "chopin", "oo-vr",  "oo-vr-affinity"};
const std::vector<int> kGpmCounts = {2, 4, 8, 16};

// Published: Kim et al., "GPUpd", MICRO 2017: speed-up over one GPU at 16
// GPUs, geometric mean of 8 game traces, GPUpd against primitive
// duplication. Ren and Lis, "CHOPIN", HPCA 2021: CHOPIN over GPUpd at 8
// GPUs, geometric mean and best.
constexpr double kGpupd16 = 4.98, kDuplication16 = 3.07;
constexpr double kChopinOverGpupd = 1.25, kChopinOverGpupdBest = 1.56;

// The variant naming CHOPIN's one-group bound at 8 GPMs (beyond.toml).
const std::string kChopinFrame8 = "chopin.groups=frame;gpms=8";

std::string times(double x) { return std::isfinite(x) ? fmt::format("{:.2f}x", x) : "n/a"; }
std::string num(double x, int digits = 2) { return std::isfinite(x) ? fmt::format("{:.{}f}", x, digits) : "n/a"; }
std::string pct(double ratio) {
  if (!std::isfinite(ratio)) return "n/a";
  const double p = (ratio - 1) * 100;
  return std::abs(p) < 0.5 ? "0%" : fmt::format("{:+.0f}%", p);
}

// A markdown table cell: no column breaks, no control characters.
std::string cell(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += "\\|";
    else if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out;
}

struct Study {
  const PaperResults& r;
  const PaperOptions& o;
  Figures F{r, o};

  const SchemeResult* at(const std::string& scene, const std::string& scheme, const std::string& variant = "") const {
    return r.find(scene, o.sweep_resolution, scheme, variant);
  }
  // Over the baseline on the machine as given (4 GPMs, 64 GB/s links).
  double speedup(const std::string& scene, const std::string& scheme, const std::string& variant = "") const {
    return F.speedup(scene, o.sweep_resolution, scheme, variant);
  }
  // Over one GPM alone (single-gpm).
  double over_one(const std::string& scene, const std::string& scheme, int gpms) const { return F.gpms(scene, scheme, gpms); }
  double over_one(const std::string& scene, const std::string& scheme, const std::string& variant) const {
    return F.speedup(scene, o.sweep_resolution, scheme, variant, "single-gpm");
  }
  double mean(const std::function<double(const std::string&)>& f) const { return F.mean(f); }
  std::vector<double> across(const std::function<double(const std::string&)>& f) const { return F.across(f); }
  double best(const std::function<double(const std::string&)>& f) const {
    const std::vector<double> v = across(f);
    return v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end());
  }
  // Bytes of category c per frame at 4 GPMs, mean over the scenes.
  double category_bytes(const std::string& scheme, int c) const {
    double sum = 0;
    int n = 0;
    for (const auto& s : r.scenes)
      if (const SchemeResult* x = at(s, scheme)) {
        sum += double(x->inter_gpm_bytes[size_t(c)]);
        ++n;
      }
    return n ? sum / n : std::nan("");
  }
  double balance(const std::string& scene, const std::string& scheme) const {
    const SchemeResult* x = at(scene, scheme);
    return x ? x->best_to_worst() : std::nan("");
  }
  // Vertex shader invocations of `scheme` at `variant` over one GPM's.
  double vertex_factor(const std::string& scene, const std::string& scheme, const std::string& variant) const {
    const SchemeResult* x = at(scene, scheme, variant);
    const SchemeResult* one = at(scene, "single-gpm");
    return x && one && one->vertices ? double(x->vertices) / double(one->vertices) : std::nan("");
  }
  double metric(const std::string& scene, const std::string& scheme, const std::string& name,
                const std::string& variant = "") const {
    const SchemeResult* x = at(scene, scheme, variant);
    return x ? scheme_metric(*x, name) : std::nan("");
  }
};

std::string link_name(double gbps) { return gbps >= 1000 ? "1 TB/s" : fmt::format("{:.0f} GB/s", gbps); }

}  // namespace

void write_beyond_plots(const PaperResults& r, const PaperOptions& o, const std::string& dir) {
  const Study S{r, o};
  const fs::path d(dir);
  std::error_code ec;
  fs::create_directories(d, ec);
  const auto write = [&](const std::string& name, const std::string& svg) {
    write_output_file((d / name).string(), svg, "plot");
  };
  // Speed-up over the baseline at 4 GPMs, per scene and geomean.
  std::vector<std::string> groups = r.scenes;
  groups.push_back("geomean");
  std::vector<std::vector<double>> sp;
  for (const auto& s : r.scenes) {
    sp.emplace_back();
    for (const auto& sc : kSchemes) sp.back().push_back(S.speedup(s, sc));
  }
  sp.emplace_back();
  for (const auto& sc : kSchemes) sp.back().push_back(S.mean([&](const std::string& s) { return S.speedup(s, sc); }));
  write("speedup.svg", bar_chart("Speed-up over the baseline, 4 GPMs (" + o.sweep_resolution + ")", "speed-up (baseline = 1)",
                                 groups, kSchemes, sp, 1.0));
  // Over one GPM against the GPM count.
  std::vector<double> gx;
  std::vector<std::string> gn;
  for (int n : kGpmCounts) {
    gx.push_back(n);
    gn.push_back(std::to_string(n));
  }
  std::vector<std::vector<double>> gv;
  for (const auto& sc : kSwept) {
    gv.emplace_back();
    for (int n : kGpmCounts) gv.back().push_back(S.mean([&](const std::string& s) { return S.over_one(s, sc, n); }));
  }
  write("gpms.svg", line_chart("Speed-up over one GPM (geomean of scenes)", "GPMs", "speed-up", gx, gn, kSwept, gv, true));
  // Against the link bandwidth.
  std::vector<double> lx;
  std::vector<std::string> ln;
  for (const auto& [bw, gbps] : kLinks) {
    lx.push_back(gbps);
    ln.push_back(gbps >= 1000 ? "1 TB/s" : fmt::format("{:.0f}", gbps));
  }
  std::vector<std::vector<double>> lv;
  for (const auto& sc : kSwept) {
    lv.emplace_back();
    for (const auto& link : kLinks) {
      const std::string& bw = link.first;
      lv.back().push_back(S.mean([&](const std::string& s) { return S.F.link(s, sc, bw); }));
    }
  }
  write("links.svg", line_chart("Speed-up over the baseline at " + machine_value(o, "link.bandwidth") + ", " +
                                    machine_value(o, "gpms") + " GPMs (geomean of scenes)",
                                "link bandwidth (GB/s)", "speed-up", lx, ln, kSwept, lv, true));
  // Traffic by category.
  std::vector<std::string> categories;
  for (int c = 0; c < kCategories; ++c) categories.push_back(category_name(Category(c)));
  std::vector<std::vector<double>> tv;
  for (const auto& sc : kSchemes) {
    tv.emplace_back();
    for (int c = 0; c < kCategories; ++c) tv.back().push_back(S.category_bytes(sc, c) / 1e6);
  }
  write("traffic.svg", bar_chart("Inter-GPM traffic by category, 4 GPMs (MB per frame, mean of scenes)", "MB per frame", kSchemes,
                                 categories, tv, 0.0));
  // Balance.
  std::vector<std::vector<double>> bv;
  for (const auto& s : r.scenes) {
    bv.emplace_back();
    for (const auto& sc : kSchemes) bv.back().push_back(S.balance(s, sc));
  }
  write("balance.svg", bar_chart("Busiest GPM's busy time over the least busy one's, 4 GPMs", "best-to-worst (1 = even)",
                                 r.scenes, kSchemes, bv, 1.0));
}

void write_beyond_outputs(const PaperResults& r, const PaperOptions& o, const std::string& dir) {
  std::string csv =
      "scene,resolution,scheme,variant,latency_ms,speedup_vs_baseline,speedup_vs_one_gpm,best_to_worst,inter_gpm_bytes";
  for (int c = 0; c < kCategories; ++c) csv += std::string(",") + category_name(Category(c));
  csv += "\n";
  const auto quoted = [](const std::string& s) {
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  for (const auto& x : r.runs) {
    // Against the baseline and one GPM on the machine as given (variant "").
    const auto over = [&](const std::string& scheme) {
      const SchemeResult* b = r.find(x.scene, x.resolution, scheme);
      return b ? b->frame_latency_s / x.result.frame_latency_s : std::nan("");
    };
    const double vs_base = over("baseline"), vs_one = over("single-gpm");
    csv +=
        fmt::format("{},{},{},{},{:.6f},{:.4f},{:.4f},{:.4f},{}", quoted(x.scene), x.resolution, x.scheme, quoted(x.variant),
                    x.result.frame_latency_s * 1e3, vs_base, vs_one, x.result.best_to_worst(), x.result.total_inter_gpm_bytes());
    for (int c = 0; c < kCategories; ++c) csv += fmt::format(",{}", x.result.inter_gpm_bytes[size_t(c)]);
    csv += "\n";
  }
  write_output_file((fs::path(dir) / "runs.csv").string(), csv, "output");
  write_beyond_plots(r, o, (fs::path(dir) / "img" / "beyond").string());
}

namespace {

class Doc {
 public:
  Doc(const PaperResults& results, const PaperOptions& options, std::string plots_link)
      : S{results, options}, r(results), o(options), plots(std::move(plots_link)) {}

  std::string write() {
    intro();
    at_four();
    scaling();
    links();
    traffic();
    balance();
    gpupd();
    chopin();
    affinity();
    return out;
  }

 private:
  void figure(const std::string& alt, const std::string& file) {
    if (!plots.empty()) out += "\n![" + alt + "](" + plots + "/" + file + ")\n";
  }
  // A table of schemes (rows) by scenes (columns) and their geomean.
  void scene_table(const std::vector<std::string>& schemes,
                   const std::function<double(const std::string&, const std::string&)>& f,
                   const std::function<std::string(double)>& show) {
    out += "\n| scheme |";
    for (const auto& s : r.scenes) out += fmt::format(" {} |", cell(s));
    out += " geomean |\n|---|";
    for (size_t k = 0; k <= r.scenes.size(); ++k) out += "---:|";
    out += "\n";
    for (const auto& sc : schemes) {
      out += fmt::format("| `{}` |", sc);
      for (const auto& s : r.scenes) out += fmt::format(" {} |", show(f(s, sc)));
      out += fmt::format(" {} |\n", show(S.mean([&](const std::string& s) { return f(s, sc); })));
    }
  }

  void intro() {
    out += "# Beyond the paper: the state of the art on one model\n\n";
    out += "Generated by `oovr beyond` from the runs of experiments/beyond.toml; do not edit. As run:\n\n```\n" + o.command +
           "\n```\n\n";
    out += fmt::format(
        "The OO-VR paper compares OO-VR with the baseline, AFR and tile- and object-level split-frame rendering. This study "
        "sets the schemes the field uses besides those on the same model: primitive duplication (`sfr-v`, `sfr-h`: every GPM "
        "receives every draw and renders its own strip), Equalizer's load-balanced strips (`sfr-lb`), the per-eye split VR "
        "drivers ship (`per-eye`), GPUpd (Kim et al., MICRO 2017: `gpupd`) and CHOPIN (Ren and Lis, HPCA 2021: `chopin`), "
        "with OO-VR (`oo-vr`) and oovr's own OO-VR with screen affinity (`oo-vr-affinity`); docs/model.md says what each "
        "does and assumes. The machine is the paper's Table 1{} ({} GPMs, {} links, {}) unless a section says otherwise; "
        "{} frames from frame {} at {}, after a warm-up pass over them; speed-ups are ratios of frame latencies.\n\n",
        [&] {
          // Another machine (oovr beyond --config/--set): its changes, with where they came from.
          std::string changed;
          for (const MachineChange& c : machine_changes(o.machine, o.machine_sources))
            changed +=
                (changed.empty() ? " with " : ", ") + ("`" + c.key + "` = " + c.value + " (" + markdown_text(c.source) + ")");
          return changed;
        }(),
        o.spec.memory.gpms, format_bandwidth(o.spec.memory.link_bandwidth), o.spec.memory.topology, o.frames, o.first_frame,
        o.sweep_resolution);
    out += "Scenes measured:";
    for (size_t k = 0; k < r.scenes.size(); ++k) {
      const auto it = r.stats.find(r.scenes[k]);
      out += fmt::format("{}{}", k ? "; " : " ", cell(r.scenes[k]));
      if (it != r.stats.end())
        out += fmt::format(" ({} draws, {} triangles, vertex work {:.0f}% of shader work)", it->second.draws,
                           it->second.triangles, it->second.vertex_share * 100);
    }
    out += ".";
    if (!r.skipped.empty()) {
      out += " Skipped:";
      for (const auto& s : r.skipped) out += fmt::format(" {};", cell(s));
      out.back() = '.';
    }
    out += fmt::format(" {} runs.\n", r.runs.size());
  }

  void at_four() {
    out += fmt::format("\n## At {} GPMs\n\nSpeed-up over the baseline:\n", o.spec.memory.gpms);
    scene_table(
        kSchemes, [&](const std::string& s, const std::string& sc) { return S.speedup(s, sc); }, times);
    figure("Speed-up over the baseline", "speedup.svg");
  }

  void scaling() {
    out +=
        "\n## Against the GPM count\n\nSpeed-up over one GPM alone (`single-gpm`), geometric mean of the scenes:\n\n| scheme |";
    for (int n : kGpmCounts) out += fmt::format(" {} GPMs |", n);
    out += "\n|---|";
    for (size_t k = 0; k < kGpmCounts.size(); ++k) out += "---:|";
    out += "\n";
    for (const auto& sc : kSwept) {
      out += fmt::format("| `{}` |", sc);
      for (int n : kGpmCounts)
        out += fmt::format(" {} |", times(S.mean([&](const std::string& s) { return S.over_one(s, sc, n); })));
      out += "\n";
    }
    figure("Speed-up over one GPM against GPM count", "gpms.svg");
  }

  void links() {
    out += "\n## Against the link bandwidth\n\nSpeed-up over the baseline at " + machine_value(o, "link.bandwidth") +
           ", geometric mean of the scenes:\n\n| scheme |";
    for (const auto& [bw, gbps] : kLinks) out += fmt::format(" {} |", link_name(gbps));
    out += " 32 GB/s to 1 TB/s |\n|---|";
    for (size_t k = 0; k <= kLinks.size(); ++k) out += "---:|";
    out += "\n";
    for (const auto& sc : kSwept) {
      out += fmt::format("| `{}` |", sc);
      std::vector<double> v;
      for (const auto& link : kLinks) {
        const std::string& bw = link.first;
        v.push_back(S.mean([&](const std::string& s) { return S.F.link(s, sc, bw); }));
        out += fmt::format(" {} |", times(v.back()));
      }
      out += fmt::format(" {} |\n", pct(v.back() / v.front()));
    }
    figure("Speed-up against link bandwidth", "links.svg");
  }

  void traffic() {
    out += "\n## Traffic between GPMs by category\n\nMB per frame, mean of the scenes:\n\n| scheme |";
    for (int c = 0; c < kCategories; ++c) out += std::string(" ") + category_name(Category(c)) + " |";
    out += " all |\n|---|";
    for (int c = 0; c <= kCategories; ++c) out += "---:|";
    out += "\n";
    for (const auto& sc : kSchemes) {
      out += fmt::format("| `{}` |", sc);
      double all = 0;
      for (int c = 0; c < kCategories; ++c) {
        const double b = S.category_bytes(sc, c);
        all += b;
        out += fmt::format(" {} |", num(b / 1e6, 1));
      }
      out += fmt::format(" {} |\n", num(all / 1e6, 1));
    }
    figure("Traffic by category", "traffic.svg");
  }

  void balance() {
    out += "\n## Balance\n\nThe busiest GPM's busy time over the least busy one's (1: even):\n";
    scene_table(
        kSchemes, [&](const std::string& s, const std::string& sc) { return S.balance(s, sc); }, [](double x) { return num(x); });
    figure("Balance", "balance.svg");
  }

  void gpupd() {
    const auto g16 = [&](const std::string& s) { return S.over_one(s, "gpupd", 16); };
    const auto v16 = [&](const std::string& s) { return S.over_one(s, "sfr-v", 16); };
    const auto ratio = [&](const std::string& s) { return g16(s) / v16(s); };
    const double mine = S.mean(ratio), published = kGpupd16 / kDuplication16;
    out += "\n## GPUpd against primitive duplication\n\n";
    out += fmt::format(
        "Published (Kim et al., MICRO 2017): at 16 GPUs GPUpd is {:.2f}x one GPU and primitive duplication {:.2f}x (eight "
        "game traces), GPUpd {:.2f}x primitive duplication. oovr at 16 GPMs, over one GPM (primitive duplication is `sfr-v`, "
        "whose strips are GPUpd's regions in oovr, so that the two differ only in how geometry reaches the strips):\n\n",
        kGpupd16, kDuplication16, published);
    out +=
        "| scene | `gpupd` | `sfr-v` | `gpupd` / `sfr-v` | vertex shading of `sfr-v` | of `gpupd` |\n"
        "|---|---:|---:|---:|---:|---:|\n";
    for (const auto& s : r.scenes)
      out += "| " + cell(s) + " | " + times(g16(s)) + " | " + times(v16(s)) + " | " + times(ratio(s)) + " | " +
             times(S.vertex_factor(s, "sfr-v", "gpms=16")) + " | " + times(S.vertex_factor(s, "gpupd", "gpms=16")) + " |\n";
    out += "| geomean | " + times(S.mean(g16)) + " | " + times(S.mean(v16)) + " | " + times(mine) + " | | |\n";
    out += fmt::format(
        "\nThe vertex shading columns are the vertex shader's invocations over one GPM's. oovr's GPUpd stands {} against "
        "primitive duplication than the published {:.2f}x ({} here). Why they differ:\n\n",
        mine < published ? "lower" : "higher", published, times(mine));
    const double dup = S.mean([&](const std::string& s) { return S.vertex_factor(s, "sfr-v", "gpms=16"); });
    out += fmt::format(
        "- **Duplication as oovr charges it.** GPUpd's primitive duplication transforms every primitive on every GPU, 16 "
        "times at 16 GPUs. oovr's `sfr-v` sends every draw to every GPM, but a GPM transforms only the draws that reach its "
        "strip, once per eye they cover (the trace says where a draw lands): {} one GPM's vertex shading at 16 GPMs "
        "(geometric mean){}.\n",
        times(dup), dup < 16 ? ", not 16x: what GPUpd saves is smaller here than there" : "");
    out +=
        "- **Projection costs the whole vertex shader** (`gpupd.projection_cost` = 1): GPUpd runs only its position "
        "part, whose share oovr's traces do not give, and so its projection costs less there than here.\n";
    double lo = 1, hi = 0;
    for (const auto& [scene, st] : r.stats) {
      lo = std::min(lo, st.vertex_share);
      hi = std::max(hi, st.vertex_share);
    }
    out += fmt::format(
        "- **The scenes are light in geometry.** Vertex work is {:.0f}% to {:.0f}% of the shader work here. GPUpd's gain is "
        "the geometry that duplication repeats; where there is this little of it, there is little to gain.\n",
        lo * 100, hi * 100);
    const double gpupd_vertices = S.mean([&](const std::string& s) { return S.vertex_factor(s, "gpupd", "gpms=16"); });
    out += fmt::format(
        "- **What GPUpd adds.** Each batch is projected, then every GPM sends its primitive IDs in turn (API order), then "
        "the strips render: a GPM renders nothing of a batch before the whole exchange is over (runahead overlaps only the "
        "next batch's projection). oovr's GPUpd shades {} one GPM's vertices at 16 GPMs against `sfr-v`'s {}, {}, "
        "so what it saves in vertex work {} what its phases cost.\n",
        times(gpupd_vertices), times(dup), gpupd_vertices < dup ? "fewer" : "no fewer",
        std::isfinite(mine) && mine < 1 ? "falls short of" : "outweighs");
  }

  void chopin() {
    const auto ratio = [&](const std::string& s) { return S.over_one(s, "chopin", 8) / S.over_one(s, "gpupd", 8); };
    const auto bound = [&](const std::string& s) { return S.over_one(s, "chopin", kChopinFrame8) / S.over_one(s, "gpupd", 8); };
    const double mine = S.mean(ratio);
    out += "\n## CHOPIN against GPUpd\n\n";
    out += fmt::format(
        "Published (Ren and Lis, HPCA 2021): at 8 GPUs CHOPIN is {:.2f}x GPUpd (geometric mean), up to {:.2f}x. oovr at 8 "
        "GPMs:\n\n",
        kChopinOverGpupd, kChopinOverGpupdBest);
    out +=
        "| scene | `chopin` / `gpupd` | composition groups (blended) | as one group / `gpupd` | best-to-worst |\n"
        "|---|---:|---:|---:|---:|\n";
    for (const auto& s : r.scenes) {
      const SchemeResult* x = S.at(s, "chopin", "gpms=8");
      out += "| " + cell(s) + " | " + times(ratio(s)) + " | " + num(S.metric(s, "chopin", "groups", "gpms=8"), 0) + " (" +
             num(S.metric(s, "chopin", "groups.blended", "gpms=8"), 0) + ") | " + times(bound(s)) + " | " +
             (x ? num(x->best_to_worst()) : "n/a") + " |\n";
    }
    out += "| geomean | " + times(mine) + " | | " + times(S.mean(bound)) + " | |\n";
    out += fmt::format(
        "\noovr's CHOPIN is {} GPUpd (geometric mean; best {}), against the published {:.2f}x (best {:.2f}x). Why they "
        "differ:\n\n",
        times(mine), times(S.best(ratio)), kChopinOverGpupd, kChopinOverGpupdBest);
    out += fmt::format(
        "- **Composition groups are barriers.** A group's sub-images are composed before the next group starts, and oovr "
        "cuts a group wherever blending switches, the only synchronisation point the traces carry (the groups column). "
        "Composed as one opaque group (`chopin.groups = frame`, a bound that composes blended draws out of order) CHOPIN is "
        "{} GPUpd instead of {}. CHOPIN's traces cut groups at render-target switches and clears.\n",
        times(S.mean(bound)), times(mine));
    out += fmt::format(
        "- **Large draws are not split** (CHOPIN's option, not done): a draw goes whole to one GPM, so a scene with a few "
        "large draws leaves one GPM with most fragments (best-to-worst up to {} at 8 GPMs here).\n",
        num(S.best([&](const std::string& s) {
          const SchemeResult* x = S.at(s, "chopin", "gpms=8");
          return x ? x->best_to_worst() : std::nan("");
        })));
    out +=
        "- **oovr's GPUpd is not CHOPIN's GPUpd.** CHOPIN measures against its own reimplementation on ATTILA. oovr's "
        "charges GPUpd's projection the whole vertex shader, which makes it slower than a position-only projection "
        "would, and so CHOPIN's ratio larger than it would be.\n";
  }

  void affinity() {
    const auto gain = [&](const std::string& s) { return S.speedup(s, "oo-vr-affinity") / S.speedup(s, "oo-vr"); };
    const auto traffic = [&](const std::string& s) {
      const SchemeResult* a = S.at(s, "oo-vr-affinity");
      const SchemeResult* b = S.at(s, "oo-vr");
      return a && b && b->total_inter_gpm_bytes() ? double(a->total_inter_gpm_bytes()) / double(b->total_inter_gpm_bytes())
                                                  : std::nan("");
    };
    out += "\n## oovr's idea: OO-VR with screen affinity\n\n";
    out += fmt::format(
        "What oovr measures of OO-VR is that, its texture reads made local by pre-allocation, its links carry the pixels a "
        "GPM renders outside its own strip: their colour to the strip's owner and their depth tests in the owner's depth "
        "buffer (the depth and composition columns above: {} and {} MB per frame, of {} MB). `oo-vr-affinity` has the "
        "distribution engine send a batch to the GPM for which its predicted free time plus the link time of those pixels "
        "there is least, with where its objects' pixels fall taken from the previous frame. Against `oo-vr` at {} GPMs:\n\n",
        num(S.category_bytes("oo-vr", int(Category::depth)) / 1e6, 1),
        num(S.category_bytes("oo-vr", int(Category::composition)) / 1e6, 1),
        num(
            [&] {
              double all = 0;
              for (int c = 0; c < kCategories; ++c) all += S.category_bytes("oo-vr", c);
              return all / 1e6;
            }(),
            1),
        o.spec.memory.gpms);
    out += "| scene | speed-up | traffic | batches moved by affinity |\n|---|---:|---:|---:|\n";
    for (const auto& s : r.scenes)
      out += "| " + cell(s) + " | " + pct(gain(s)) + " | " + pct(traffic(s)) + " | " +
             num(S.metric(s, "oo-vr-affinity", "affine_batches"), 0) + " of " + num(S.metric(s, "oo-vr", "batches"), 0) + " |\n";
    const auto at = [&](const std::string& variant) {
      return S.mean(
          [&](const std::string& s) { return S.F.speedup(s, o.sweep_resolution, "oo-vr-affinity", variant, "oo-vr", variant); });
    };
    const double mean = S.mean(gain);
    out += fmt::format("\nGeometric mean {} at {} GPMs; {} at 8, {} at 16; {} with 32 GB/s links. ", pct(mean),
                       o.spec.memory.gpms, pct(at("gpms=8")), pct(at("gpms=16")), pct(at("link.bandwidth=32GBps")));
    if (std::isfinite(mean) && mean < 1.03)
      out +=
          "The idea does not pay much here. What limits it: a batch's pixels spread over the strips, so that no GPM is "
          "much cheaper for it than another (both eyes of an object are drawn by one GPM, while DHC's strips give the "
          "left eye to some GPMs and the right to others), an idle GPM takes the next batch at once, and the split moves "
          "leftover work whatever its pixels cost. Affinity would need ownership that follows the objects, which DHC's "
          "fixed strips do not give.\n";
    else out += "What it gains is the link time of the pixels it keeps on their owners (the traffic column).\n";
  }

  Study S;
  const PaperResults& r;
  const PaperOptions& o;
  std::string plots;
  std::string out;
};

}  // namespace

void write_beyond_doc(const PaperResults& results, const PaperOptions& options, const std::string& path,
                      const std::string& plots_dir) {
  Doc d(results, options, plots_link(path, plots_dir));
  write_output_file(path, d.write(), "study document");
}

}  // namespace oovr
