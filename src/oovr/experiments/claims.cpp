#include "oovr/experiments/claims.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
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

  // A [[claim.check]] of `claim` (its values read already).
  ClaimCheck check(const toml::table& t, const Claim& claim) const {
    for (const auto& [k, v] : t)
      if (k != "part" && k != "says" && k != "over" && k != "when")
        fail(v, claim.id + ": a check has no key '" + std::string(k.str()) + "' (part, says, over, when)");
    ClaimCheck out;
    out.part = text(t, "part", false);
    out.says = text(t, "says");
    out.over = text(t, "over");
    if (out.over != "all" && out.over != "most" && out.over != "mean")
      fail(t, claim.id + ": over '" + out.over + "' (all, most or mean)");
    const toml::node* w = t.get("when");
    const toml::array* list = w ? w->as_array() : nullptr;
    if (!list || list->empty()) fail(t, claim.id + ": a check needs when = [ conditions ]");
    for (const auto& cn : *list) {
      const toml::table* ct = cn.as_table();
      if (!ct) fail(cn, claim.id + ": a condition is a table such as { value = \"sfr-v\", above = 1 }");
      out.when.push_back(condition(*ct, claim));
    }
    return out;
  }

 private:
  std::string m_name;

  const ClaimValue& value_of(const toml::node& at, const Claim& claim, const std::string& label) const {
    for (const ClaimValue& v : claim.values)
      if (v.label == label) return v;
    std::string labels;
    for (const ClaimValue& v : claim.values) labels += (labels.empty() ? "'" : ", '") + v.label + "'";
    fail(at, claim.id + " has no value '" + label + "' (its values: " + labels + ")");
  }

  ClaimCondition condition(const toml::table& t, const Claim& claim) const {
    static const char* ops[] = {"above", "below", "at_least", "at_most", "near", "rising"};
    ClaimCondition c;
    const toml::node* op = nullptr;
    for (const auto& [k, v] : t) {
      const std::string key(k.str());
      if (key == "value" || key == "gain") continue;
      if (std::find(std::begin(ops), std::end(ops), key) == std::end(ops))
        fail(v, claim.id + ": a condition has no key '" + key + "' (value, above, below, at_least, at_most, near, rising, gain)");
      if (op) fail(v, claim.id + ": a condition compares one way (" + c.op + " and " + key + ")");
      c.op = key;
      op = &v;
    }
    if (!op) fail(t, claim.id + ": a condition needs one of above, below, at_least, at_most, near, rising");
    if (c.op == "rising") {
      const toml::array* labels = op->as_array();
      if (!labels || labels->size() < 2) fail(*op, claim.id + ": rising takes two or more value labels");
      for (const auto& l : *labels) {
        if (!l.as_string()) fail(l, claim.id + ": rising takes value labels");
        c.rising.push_back(value_of(l, claim, l.as_string()->get()).label);
      }
      if (t.get("value") || t.get("gain")) fail(t, claim.id + ": rising names its values itself");
      return c;
    }
    const ClaimValue& v = value_of(t, claim, text(t, "value"));
    c.value = v.label;
    if (c.op == "near") {
      if (!op->as_boolean() || !op->as_boolean()->get()) fail(*op, claim.id + ": near takes true");
      if (!v.tolerance) fail(*op, claim.id + " (" + v.label + "): near needs the value's tolerance");
      if (t.get("gain")) fail(t, claim.id + ": gain compares with another value");
      return c;
    }
    if (const auto* s = op->as_string()) c.other = value_of(*op, claim, s->get()).label;
    else if (const auto d = op->value<double>(); d && std::isfinite(*d)) c.number = *d;
    else fail(*op, claim.id + ": " + c.op + " takes a number or a value's label");
    if (const toml::node* g = t.get("gain")) {
      const auto d = g->value<double>();
      if (!d || !std::isfinite(*d) || *d <= 0) fail(*g, claim.id + ": gain takes a positive number");
      if (c.other.empty()) fail(*g, claim.id + ": gain compares with another value");
      c.gain = *d;
    }
    return c;
  }
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
      static const char* measures[] = {"speedup",       "latency",        "throughput", "traffic",
                                       "best_to_worst", "engine_storage", "energy",     "link_energy"};
      if (std::find(std::begin(measures), std::end(measures), x.measure) == std::end(measures))
        r.fail(v, "measure '" + x.measure +
                      "' (speedup, latency, throughput, traffic, best_to_worst, engine_storage, energy, link_energy)");
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
    if (const toml::node* cn = c.get("check")) {
      const toml::array* checks = cn->as_array();
      if (!checks || !checks->is_array_of_tables()) r.fail(*cn, claim.id + ": check takes [[claim.check]] tables");
      for (const auto& kn : *checks) claim.checks.push_back(r.check(*kn.as_table(), claim));
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
  static const nlohmann::ordered_json d = machine_values(Config{});
  return d;
}

}  // namespace

nlohmann::ordered_json machine_values(const Config& config) {
  Config c = config;
  check_config(c);
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [k, e] : c.entries()) j[k] = base_value(e);
  return j;
}

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
    nlohmann::ordered_json checks = nlohmann::ordered_json::array();
    for (const ClaimCheck& k : c.checks) checks.push_back({{"part", k.part}, {"says", k.says}, {"over", k.over}});
    x["checks"] = checks;
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

bool on_paper_setup(const RunRecord& r, const std::string& scheme, const nlohmann::ordered_json& settings,
                    const nlohmann::ordered_json* machine) {
  if (r.scheme != scheme || r.status != "done") return false;
  for (const auto& [key, fallback] : (machine ? *machine : default_values()).items()) {
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

std::vector<std::vector<ClaimMeasured>> measure_claims(const std::vector<Claim>& claims, const std::vector<RunRecord>& runs,
                                                       const nlohmann::ordered_json* machine) {
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
        if (!on_paper_setup(*r, v.scheme, set, machine) || seen.count(group(*r))) continue;
        double x = std::nan("");
        if (v.measure == "best_to_worst") {
          x = metric(*r, "frame", "best_to_worst");
        } else if (v.measure == "engine_storage") {
          x = metric(*r, r->scheme, "engine_storage");
        } else {
          const RunRecord* ref = nullptr;
          for (const RunRecord* a : done)
            if (group(*a) == group(*r) && on_paper_setup(*a, v.against, against_set, machine)) {
              ref = a;
              break;
            }
          if (!ref) continue;
          if (v.measure == "speedup") x = metric(*ref, "frame", "latency") / metric(*r, "frame", "latency");
          else if (v.measure == "latency") x = metric(*r, "frame", "latency") / metric(*ref, "frame", "latency");
          else if (v.measure == "throughput") x = metric(*r, "frame", "throughput") / metric(*ref, "frame", "throughput");
          else {
            // Bytes between GPMs, or the energy of the memory system or of
            // its links (result_metrics.h, energy_of), over the reference's.
            const char* name = v.measure == "traffic" ? "inter_gpm_bytes" : v.measure == "energy" ? "energy" : "energy.links";
            const double b = metric(*ref, "frame", name);
            x = b != 0 ? metric(*r, "frame", name) / b : std::nan("");
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

namespace {

// `a` at most `b` (or at least), within rounding: results read back from a
// database and ratios of them differ from those computed directly in their
// last digits.
bool at_most(double a, double b) { return a <= b + 1e-9 * std::max(std::abs(a), std::abs(b)); }

bool meets(const ClaimCondition& c, const std::function<double(const std::string&)>& x, const ClaimValue& v) {
  if (c.op == "rising") {
    for (size_t i = 1; i < c.rising.size(); ++i)
      if (!at_most(x(c.rising[i - 1]), x(c.rising[i]))) return false;
    return true;
  }
  double a = x(c.value);
  if (!std::isfinite(a)) return false;
  if (c.op == "near") return std::abs(a - *v.paper) < *v.tolerance;
  double b = c.number ? *c.number : x(c.other);
  if (!std::isfinite(b)) return false;
  if (c.gain) {
    a -= 1;
    b = *c.gain * (b - 1);
  }
  if (c.op == "above") return a > b;
  if (c.op == "below") return a < b;
  if (c.op == "at_least") return at_most(b, a);
  return at_most(a, b);  // at_most
}

std::vector<std::string> labels_of(const ClaimCheck& k) {
  std::vector<std::string> out;
  for (const ClaimCondition& c : k.when) {
    for (const auto& l : c.rising) out.push_back(l);
    if (!c.value.empty()) out.push_back(c.value);
    if (!c.other.empty()) out.push_back(c.other);
  }
  return out;
}

}  // namespace

std::vector<std::vector<CheckVerdict>> judge_claims(const std::vector<Claim>& claims,
                                                    const std::vector<std::vector<ClaimMeasured>>& measured) {
  if (measured.size() != claims.size()) throw Error("judge_claims: measurements of another claims file");
  std::vector<std::vector<CheckVerdict>> out(claims.size());
  for (size_t c = 0; c < claims.size(); ++c) {
    const Claim& claim = claims[c];
    const auto index = [&](const std::string& label) {
      for (size_t k = 0; k < claim.values.size(); ++k)
        if (claim.values[k].label == label) return k;
      throw Error("judge_claims: " + claim.id + " has no value '" + label + "'");
    };
    const auto value = [&](const std::string& label) -> const ClaimValue& { return claim.values[index(label)]; };
    for (const ClaimCheck& k : claim.checks) {
      CheckVerdict v;
      const std::vector<std::string> labels = labels_of(k);
      const auto all_met = [&](const std::function<double(const std::string&)>& x) {
        for (const ClaimCondition& cond : k.when)
          if (!meets(cond, x, cond.value.empty() ? claim.values.front() : value(cond.value))) return false;
        return true;
      };
      if (k.over == "mean") {
        const auto x = [&](const std::string& label) { return measured[c][index(label)].mean; };
        v.measured = std::all_of(labels.begin(), labels.end(), [&](const std::string& l) { return std::isfinite(x(l)); });
        v.of = 1;
        v.met = v.measured && all_met(x) ? 1 : 0;
        v.holds = v.met == 1;
      } else {
        // The scenes every value of the check was measured on, in the
        // order the first value found them.
        using Group = std::pair<std::string, std::string>;
        std::vector<std::map<Group, double>> per(labels.size());
        for (size_t i = 0; i < labels.size(); ++i)
          for (const auto& [scene, resolution, x] : measured[c][index(labels[i])].per)
            per[i].emplace(Group{scene, resolution}, x);
        for (const auto& [scene, resolution, x0] : measured[c][index(labels.front())].per) {
          const Group s{scene, resolution};
          if (!std::all_of(per.begin(), per.end(), [&](const auto& m) { return m.count(s) > 0; })) continue;
          ++v.of;
          const auto x = [&](const std::string& label) {
            for (size_t i = 0; i < labels.size(); ++i)
              if (labels[i] == label) return per[i].at(s);
            return std::nan("");
          };
          if (all_met(x)) ++v.met;
        }
        v.measured = v.of > 0;
        v.holds = v.measured && (k.over == "all" ? v.met == v.of : 2 * v.met > v.of);
      }
      out[c].push_back(v);
    }
  }
  return out;
}

}  // namespace oovr
