// The paper's quantitative claims as data (experiments/paper-claims.toml,
// carried inside oovr): for each number the paper states, which two runs
// it compares, how, and the paper's value. What `oovr report` and the
// paper comparison set oovr's numbers beside.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

namespace oovr {

struct ClaimValue {
  std::string label;
  std::string measure;  // speedup, latency, throughput, traffic, best_to_worst, engine_storage, energy, link_energy
  std::string scheme;
  std::map<std::string, std::string> set;  // keys changed from the paper's setup, as --set takes them
  std::string against = "baseline";
  std::map<std::string, std::string> against_set;
  std::optional<double> paper;  // the paper's ratio (or bits); none where it gives no number
  std::string form;             // percent, times or bits
  bool about = false;
  // How near oovr's mean must come to `paper` for the comparison document
  // to count it as agreeing; none where it judges the direction only.
  std::optional<double> tolerance;
};

// One condition of a check on a claim's values (by label), on one scene
// or on their means: `value` above, below, at least or at most a number or
// another value (with `gain`, their gains, ratio - 1, the other's times
// `gain`); near the paper's number (within the value's tolerance); or, for
// `rising`, the values in that order never falling.
struct ClaimCondition {
  std::string value;
  std::string op;  // above, below, at_least, at_most, near, rising
  std::optional<double> number;
  std::string other;  // a value's label, where the comparand is one
  std::optional<double> gain;
  std::vector<std::string> rising;
};

// What oovr must show for the comparison document to count a part of the
// claim as agreeing: every condition, on `over` all or most (more than
// half) of the scenes measured, or on the means. Checks of one part hold
// together.
struct ClaimCheck {
  std::string part;  // "direction", "magnitude" or "" (the whole claim)
  std::string says;  // the check in words
  std::string over;  // all, most, mean
  std::vector<ClaimCondition> when;
};

struct Claim {
  std::string id, section, figure, what, words;
  std::string short_form;  // `short`: the numbers in the form of the document's steps and workload tables
  std::string before;      // `before`: oovr's mean at ca88d23, before issue 9's model changes, short form ("" when none)
  std::vector<ClaimValue> values;
  std::vector<ClaimCheck> checks;
};

// Parses a claims file's text. Throws Error naming `name` and what is wrong.
std::vector<Claim> parse_claims(const std::string& text, const std::string& name);
// The claims oovr carries (experiments/paper-claims.toml as built).
const std::vector<Claim>& paper_claims();

// The claims with every setting resolved to the value in base units the
// results database stores, and the machine's defaults likewise:
// {"defaults": {key: value}, "claims": [...]}.
nlohmann::ordered_json resolved_claims_json(const std::vector<Claim>& claims);

struct RunRecord;
class Config;

// One claim value measured in a results database: oovr's ratio for each
// (scene, resolution) whose runs match the value's setup, in the order the
// groups were found, and their geometric mean (NaN when none matched).
struct ClaimMeasured {
  std::vector<std::tuple<std::string, std::string, double>> per;  // (scene, resolution, ratio)
  double mean = 0;
};

// The claims' values measured in `runs` (a database's, any order; they are
// taken by sweep and position). A run matches a value's setup when it is
// its scheme, done, on the paper's machine (oovr's defaults) with only the
// value's settings changed, keys its run does not read aside; the run it is
// relative to (`against`) is the first that matches in the same scene,
// resolution, first frame and filtering. The one evaluation of the claims
// over stored runs: `oovr report` writes it for its page
// (resolved_claims_json's "measured").
// `machine`, when given, is the machine the claims' setups change instead of
// oovr's defaults (a sweep's preset): its base values, as
// machine_values gives them.
std::vector<std::vector<ClaimMeasured>> measure_claims(const std::vector<Claim>& claims, const std::vector<RunRecord>& runs,
                                                       const nlohmann::ordered_json* machine = nullptr);
// A configuration's values as results store them (base numbers, else text).
nlohmann::ordered_json machine_values(const Config& config);

// A check judged on measured values: whether it could be (some scene had
// every value it names, or every mean was measured), whether it holds, and
// on how many of the scenes its conditions held (for `mean`: 1 of 1 when
// they held on the means).
struct CheckVerdict {
  bool measured = false;
  bool holds = false;
  int met = 0, of = 0;
};
// Each claim's checks judged on its measured values (one list per claim,
// in the order of its checks): the one judgement of the claims, which the
// comparison document, the report and the tests read. A "scene" is a
// (scene, resolution) pair of the measurements.
std::vector<std::vector<CheckVerdict>> judge_claims(const std::vector<Claim>& claims,
                                                    const std::vector<std::vector<ClaimMeasured>>& measured);
// Whether a run is on the paper's machine: `scheme`, done, every key at
// oovr's default but those of `settings` (resolved as resolved_claims_json
// writes them), keys the run does not read aside.
bool on_paper_setup(const RunRecord& r, const std::string& scheme, const nlohmann::ordered_json& settings,
                    const nlohmann::ordered_json* machine = nullptr);

}  // namespace oovr
