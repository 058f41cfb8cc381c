#include "oovr/experiments/claims.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include "oovr/core/config.h"
#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/units.h"
#include "oovr/experiments/results_db.h"
#include "oovr/run/result_json.h"

namespace oovr {

namespace embedded {
extern const char* const paper_claims_toml;
}

namespace {

class ClaimReader {
 public:
  explicit ClaimReader(std::string name) : m_name(std::move(name)) {}
  [[noreturn]] void fail(const toml::node& at, const std::string& what) const {
    throw Error("bad claims '" + m_name + "' line " + std::to_string(at.source().begin.line) + ": " + what);
  }
  std::string text(const toml::table& t, const char* key, bool required = true, const std::string& fallback = "") const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (required) fail(t, std::string("missing ") + key);
      return fallback;
    }
    if (!n->as_string() || n->as_string()->get().empty()) fail(*n, std::string(key) + " takes a non-empty string");
    return n->as_string()->get();
  }
  std::map<std::string, std::string> settings(const toml::table& t, const char* key) const {
    std::map<std::string, std::string> out;
    const toml::node* n = t.get(key);
    if (!n) return out;
    const toml::table* tab = n->as_table();
    if (!tab) fail(*n, std::string(key) + " is a table of configuration keys");
    for (const auto& [k, v] : *tab) {
      if (const auto* s = v.as_string()) out[std::string(k.str())] = s->get();
      else if (const auto* i = v.as_integer()) out[std::string(k.str())] = std::to_string(i->get());
      else if (const auto* f = v.as_floating_point()) out[std::string(k.str())] = format_number(f->get());
      else fail(v, std::string(k.str()) + " takes a value as --set does");
    }
    return out;
  }

 private:
  std::string m_name;
};

}  // namespace

std::vector<Claim> parse_claims(const std::string& text, const std::string& name) {
  check_toml_text(text, name);
  toml::table t;
  try {
    t = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw Error("bad claims '" + name + "' line " + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
  }
  const ClaimReader r(name);
  const toml::array* list = t["claim"].as_array();
  if (!list || !list->is_array_of_tables()) throw Error("bad claims '" + name + "': no [[claim]] tables");
  std::vector<Claim> out;
  for (const auto& node : *list) {
    const toml::table& c = *node.as_table();
    Claim claim;
    claim.id = r.text(c, "id");
    claim.section = r.text(c, "section");
    claim.figure = r.text(c, "figure");
    claim.what = r.text(c, "what");
    claim.words = r.text(c, "words");
    claim.short_form = r.text(c, "short");
    claim.before = r.text(c, "before", false);
    const toml::array* values = c["value"].as_array();
    if (!values || !values->is_array_of_tables() || values->empty()) r.fail(c, claim.id + " has no [[claim.value]]");
    for (const auto& vn : *values) {
      const toml::table& v = *vn.as_table();
      ClaimValue x;
      x.label = r.text(v, "label");
      x.measure = r.text(v, "measure");
      static const char* measures[] = {"speedup", "latency", "throughput", "traffic", "best_to_worst", "engine_storage"};
      if (std::find(std::begin(measures), std::end(measures), x.measure) == std::end(measures))
        r.fail(v, "measure '" + x.measure + "' (speedup, latency, throughput, traffic, best_to_worst, engine_storage)");
      x.scheme = r.text(v, "scheme");
      x.set = r.settings(v, "set");
      x.against = r.text(v, "against", false, "baseline");
      x.against_set = r.settings(v, "against_set");
      if (const toml::node* p = v.get("paper")) {
        const auto d = p->value<double>();
        if (!d || !std::isfinite(*d) || *d <= 0) r.fail(*p, "paper takes a positive number");
        x.paper = *d;
      }
      x.form = r.text(v, "form");
      if (x.form != "percent" && x.form != "times" && x.form != "bits") r.fail(v, "form '" + x.form + "' (percent, times, bits)");
      if (const toml::node* tn = v.get("tolerance")) {
        const auto d = tn->value<double>();
        if (!d || !std::isfinite(*d) || *d <= 0) r.fail(*tn, "tolerance takes a positive number");
        if (!x.paper) r.fail(*tn, "tolerance without the paper's number");
        x.tolerance = *d;
      }
      if (const toml::node* a = v.get("about")) {
        if (!a->as_boolean()) r.fail(*a, "about takes true or false");
        x.about = a->as_boolean()->get();
      }
      claim.values.push_back(std::move(x));
    }
    out.push_back(std::move(claim));
  }
  return out;
}

const std::vector<Claim>& paper_claims() {
  static const std::vector<Claim> claims = parse_claims(embedded::paper_claims_toml, "experiments/paper-claims.toml");
  return claims;
}

namespace {

// Each setting as the database stores it: the number in base units, or the
// readable value for keys without one.
nlohmann::ordered_json resolve(const std::map<std::string, std::string>& set, const std::string& what) {
  Config c;
  for (const auto& [k, v] : set) c.set(k, v);
  try {
    check_config(c);
  } catch (const Error& e) {
    throw Error(what + ": " + e.what());
  }
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [k, v] : set) out[k] = base_value(c.entries().at(k));
  return out;
}

// The machine's defaults as results store them (base values).
const nlohmann::ordered_json& default_values() {
  static const nlohmann::ordered_json d = [] {
    Config defaults;
    check_config(defaults);
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    for (const auto& [k, e] : defaults.entries()) j[k] = base_value(e);
    return j;
  }();
  return d;
}

}  // namespace

nlohmann::ordered_json resolved_claims_json(const std::vector<Claim>& claims) {
  nlohmann::ordered_json j;
  j["defaults"] = default_values();
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const Claim& c : claims) {
    nlohmann::ordered_json x;
    x["id"] = c.id;
    x["section"] = c.section;
    x["figure"] = c.figure;
    x["what"] = c.what;
    x["words"] = c.words;
    x["short"] = c.short_form;
    nlohmann::ordered_json values = nlohmann::ordered_json::array();
    for (const ClaimValue& v : c.values) {
      nlohmann::ordered_json y;
      y["label"] = v.label;
      y["measure"] = v.measure;
      y["scheme"] = v.scheme;
      y["set"] = resolve(v.set, c.id + " (" + v.label + ")");
      y["against"] = v.against;
      y["against_set"] = resolve(v.against_set, c.id + " (" + v.label + ")");
      if (v.paper) y["paper"] = *v.paper;
      y["form"] = v.form;
      y["about"] = v.about;
      if (v.tolerance) y["tolerance"] = *v.tolerance;
      values.push_back(y);
    }
    x["values"] = values;
    list.push_back(x);
  }
  j["claims"] = list;
  return j;
}

namespace {

// A stored configuration entry's value: its base number, else its text.
const nlohmann::ordered_json* stored_value(const nlohmann::ordered_json& config, const std::string& key) {
  const auto it = config.find(key);
  if (it == config.end() || !it->is_object()) return nullptr;
  if (it->contains("base")) return &it->at("base");
  if (it->contains("value")) return &it->at("value");
  return nullptr;
}

double metric(const RunRecord& r, const std::string& location, const std::string& name) {
  for (const Metric& m : r.metrics)
    if (m.location == location && m.metric == name) return m.value;
  return std::nan("");
}

}  // namespace

bool on_paper_setup(const RunRecord& r, const std::string& scheme, const nlohmann::ordered_json& settings) {
  if (r.scheme != scheme || r.status != "done") return false;
  for (const auto& [key, fallback] : default_values().items()) {
    const bool set = settings.contains(key);
    const nlohmann::ordered_json& want = set ? settings.at(key) : fallback;
    const nlohmann::ordered_json* have = stored_value(r.config, key);
    if (!have) {
      if (set) return false;
      continue;  // a key of another scheme's own section, which the run does not read
    }
    if (want.is_number() && have->is_number()) {
      const double w = want.get<double>(), h = have->get<double>();
      if (std::abs(h - w) > 1e-9 * std::max(1.0, std::abs(w))) return false;
    } else if (*have != want) {
      return false;
    }
  }
  return true;
}

std::vector<std::vector<ClaimMeasured>> measure_claims(const std::vector<Claim>& claims, const std::vector<RunRecord>& runs) {
  std::vector<const RunRecord*> done;
  for (const RunRecord& r : runs)
    if (r.status == "done") done.push_back(&r);
  std::stable_sort(done.begin(), done.end(), [](const RunRecord* a, const RunRecord* b) {
    return std::tie(a->sweep, a->position) < std::tie(b->sweep, b->position);
  });
  const auto group = [](const RunRecord& r) { return std::make_tuple(r.scene, r.resolution, r.frame, r.aniso); };
  const nlohmann::ordered_json resolved = resolved_claims_json(claims)["claims"];
  std::vector<std::vector<ClaimMeasured>> out;
  for (size_t c = 0; c < claims.size(); ++c) {
    out.emplace_back();
    for (size_t k = 0; k < claims[c].values.size(); ++k) {
      const ClaimValue& v = claims[c].values[k];
      const nlohmann::ordered_json& set = resolved[c]["values"][k]["set"];
      const nlohmann::ordered_json& against_set = resolved[c]["values"][k]["against_set"];
      ClaimMeasured m;
      std::set<std::tuple<std::string, std::string, int, int>> seen;
      for (const RunRecord* r : done) {
        if (!on_paper_setup(*r, v.scheme, set) || seen.count(group(*r))) continue;
        double x = std::nan("");
        if (v.measure == "best_to_worst") {
          x = metric(*r, "frame", "best_to_worst");
        } else if (v.measure == "engine_storage") {
          x = metric(*r, r->scheme, "engine_storage");
        } else {
          const RunRecord* ref = nullptr;
          for (const RunRecord* a : done)
            if (group(*a) == group(*r) && on_paper_setup(*a, v.against, against_set)) {
              ref = a;
              break;
            }
          if (!ref) continue;
          if (v.measure == "speedup") x = metric(*ref, "frame", "latency") / metric(*r, "frame", "latency");
          else if (v.measure == "latency") x = metric(*r, "frame", "latency") / metric(*ref, "frame", "latency");
          else if (v.measure == "throughput") x = metric(*r, "frame", "throughput") / metric(*ref, "frame", "throughput");
          else if (v.measure == "traffic") {
            const double b = metric(*ref, "frame", "inter_gpm_bytes");
            x = b != 0 ? metric(*r, "frame", "inter_gpm_bytes") / b : std::nan("");
          }
        }
        if (!std::isfinite(x)) continue;
        seen.insert(group(*r));
        m.per.emplace_back(r->scene, r->resolution, x);
      }
      double logs = 0;
      size_t n = 0;
      for (const auto& [scene, resolution, x] : m.per)
        if (x > 0) {
          logs += std::log(x);
          ++n;
        }
      m.mean = n ? std::exp(logs / double(n)) : std::nan("");
      out.back().push_back(std::move(m));
    }
  }
  return out;
}

}  // namespace oovr
