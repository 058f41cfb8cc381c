#include "oovr/experiments/report.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/host.h"
#include "oovr/experiments/claims.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/svg_chart.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

namespace embedded {
extern const char* const report_py;
}

namespace fs = std::filesystem;

namespace {

// The options name what the database holds: a plot the script draws, keys
// its sweeps swept, a scheme it has runs of (the script trusts them).
void check_options(const ReportOptions& o, const std::vector<RunRecord>& runs) {
  static const std::set<std::string> plots = {"latency", "speedup", "throughput", "traffic", "energy"};
  for (const std::string& p : o.plots)
    if (!plots.count(p)) throw Error("--plots: no plot '" + p + "' (latency, speedup, throughput, traffic, energy)");
  if (o.group != "scene" && o.group != "scheme") throw Error("--group: '" + o.group + "' is not scene or scheme");
  std::set<std::string> swept, numeric, schemes;
  for (const RunRecord& r : runs) {
    for (const auto& [key, value] : r.swept) {
      swept.insert(key);
      if (value.is_number()) numeric.insert(key);
    }
    if (r.status == "done") schemes.insert(r.scheme);
  }
  const auto listed = [](const std::set<std::string>& s) {
    std::string out;
    for (const std::string& x : s) out += (out.empty() ? "" : ", ") + x;
    return out.empty() ? std::string("none") : out;
  };
  for (const std::string& k : o.x) {
    if (!swept.count(k)) throw Error("--x: the database's sweeps do not sweep '" + k + "' (they sweep " + listed(swept) + ")");
    // A figure's x axis is a number (a placement policy is a table's column).
    if (!numeric.count(k))
      throw Error("--x: '" + k +
                  "' is swept with values that are not numbers, which no figure plots against (the numeric ones: " +
                  listed(numeric) + ")");
  }
  const bool asked = o.normalise != "baseline" || std::count(o.plots.begin(), o.plots.end(), "speedup");
  if (asked && !schemes.count(o.normalise))
    throw Error("--normalise: the database has no done runs of '" + o.normalise + "' (it has " + listed(schemes) + ")");
}

}  // namespace

std::string write_report(const ReportOptions& o) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(o.db, ec))) throw Error("no results database '" + o.db + "' (oovr sweep writes one)");
  std::vector<RunRecord> runs;
  {
    // An oovr results database, of a schema this oovr reads, whole: the
    // script draws and divides what it holds. Opened read-only.
    const ResultsDb db(o.db, ResultsDb::Access::read_only);
    db.verify();
    runs = db.runs(false);  // the claims need their figures, not their images
  }
  check_options(o, runs);
  fs::create_directories(o.out, ec);
  if (ec) throw Error("cannot create the folder '" + o.out + "': " + ec.message());
  const std::string script = (fs::path(o.out) / "report.py").string();
  const std::string claims = (fs::path(o.out) / "claims.json").string();
  write_output_file(script, embedded::report_py, "report script");
  // The claims with oovr's values measured in the database (the one
  // evaluation, claims.h: the script draws what it is given), the runs on
  // the paper's machine, and the order schemes are drawn in.
  nlohmann::ordered_json context = resolved_claims_json(paper_claims());
  const auto measured = measure_claims(paper_claims(), runs);
  for (size_t c = 0; c < measured.size(); ++c)
    for (size_t k = 0; k < measured[c].size(); ++k) {
      nlohmann::ordered_json per = nlohmann::ordered_json::array();
      for (const auto& [scene, resolution, x] : measured[c][k].per) per.push_back({scene, resolution, x});
      context["claims"][c]["values"][k]["measured"] = per;
    }
  // ... and each claim's checks judged on them (every scene and resolution measured).
  const auto verdicts = judge_claims(paper_claims(), measured);
  for (size_t c = 0; c < verdicts.size(); ++c)
    for (size_t k = 0; k < verdicts[c].size(); ++k) {
      const CheckVerdict& v = verdicts[c][k];
      nlohmann::ordered_json& j = context["claims"][c]["checks"][k];
      j["verdict"] = !v.measured ? "not measured" : v.holds ? "agrees" : "differs";
      j["met"] = v.met;
      j["of"] = v.of;
    }
  nlohmann::ordered_json paper_setup = nlohmann::ordered_json::array();
  for (const RunRecord& r : runs)
    if (on_paper_setup(r, r.scheme, nlohmann::ordered_json::object())) paper_setup.push_back(r.id);
  context["paper_setup"] = paper_setup;
  context["scheme_order"] = schemes_in_order();
  nlohmann::ordered_json colours = nlohmann::ordered_json::object();
  for (const std::string& name : schemes_in_order()) colours[name] = scheme_colour(name);
  context["scheme_colours"] = colours;  // the paper's charts' colours (svg_chart.h), so every figure agrees
  context["options"] = {{"plots", o.plots}, {"x", o.x}, {"group", o.group}, {"normalise", o.normalise}, {"own_y", o.own_y}};
  write_output_file(claims, context.dump(1) + "\n", "claims");

  std::string python = o.python;
  if (python.empty()) {
    const char* env = std::getenv("OOVR_PYTHON");
    python = env && *env ? env : "/usr/bin/python3";
  }
  std::string output;
  const int rc = run_command({python, script, o.db, o.out, claims}, output);
  while (!output.empty() && output.back() == '\n') output.pop_back();
  if (rc != 0) {
    if (rc == 127) throw Error("cannot run " + python + " (set OOVR_PYTHON to a Python 3 with matplotlib)");
    if (output.find("No module named 'matplotlib'") != std::string::npos ||
        output.find("No module named 'numpy'") != std::string::npos)
      throw Error(python + " cannot import matplotlib and numpy: install python3-matplotlib (scripts/install-deps.sh does)");
    const size_t last = output.rfind('\n');
    throw Error("the report script failed (" + script + "): " + (last == std::string::npos ? output : output.substr(last + 1)));
  }
  return (fs::path(o.out) / "index.html").string();
}

}  // namespace oovr
