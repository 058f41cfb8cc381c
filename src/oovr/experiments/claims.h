// The paper's quantitative claims as data (experiments/paper-claims.toml,
// carried inside oovr): for each number the paper states, which two runs
// it compares, how, and the paper's value. What `oovr report` and the
// paper comparison set oovr's numbers beside.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace oovr {

struct ClaimValue {
  std::string label;
  std::string measure;  // speedup, latency, throughput, traffic, best_to_worst, engine_storage
  std::string scheme;
  std::map<std::string, std::string> set;  // keys changed from the paper's setup, as --set takes them
  std::string against = "baseline";
  std::map<std::string, std::string> against_set;
  std::optional<double> paper;  // the paper's ratio (or bits); none where it gives no number
  std::string form;             // percent, times or bits
  bool about = false;
};

struct Claim {
  std::string id, section, figure, what, words;
  std::string short_form;  // `short`: the numbers in the form of the document's steps and workload tables
  std::string before;      // `before`: oovr's mean at ca88d23, before issue 9's model changes, short form ("" when none)
  std::vector<ClaimValue> values;
};

// Parses a claims file's text. Throws Error naming `name` and what is wrong.
std::vector<Claim> parse_claims(const std::string& text, const std::string& name);
// The claims oovr carries (experiments/paper-claims.toml as built).
const std::vector<Claim>& paper_claims();

// The claims with every setting resolved to the value in base units the
// results database stores, and the machine's defaults likewise:
// {"defaults": {key: value}, "claims": [...]}, what the report reads.
nlohmann::ordered_json resolved_claims_json(const std::vector<Claim>& claims);

}  // namespace oovr
