#include "oovr/framework/oo_spec.h"

#include <string>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/units.h"

namespace oovr {

namespace {
// A weight on link time; beyond this it would only say "never off the owner".
constexpr double kMaxAffinity = 1000;
constexpr const char* kAffinityKind = "a number from 0 to 1000";
}  // namespace

OOSpec OOSpec::parameters(const Config& c) {
  OOSpec s;
  const OOSpec d;
  s.tsl_threshold = c.get_double("oo.tsl_threshold", d.tsl_threshold, 0, 1);
  const auto positive = [&](const char* key, int def, int max) { return int(c.get_int(key, def, 1, max)); };
  s.batch_triangles = positive("oo.batch_triangles", d.batch_triangles, 1 << 30);
  s.warmup_batches = positive("oo.warmup_batches", d.warmup_batches, 1 << 20);
  s.batch_queue = positive("oo.batch_queue", d.batch_queue, 1 << 20);
  s.tiles_per_unit = positive("oo.tiles_per_unit", d.tiles_per_unit, 1 << 20);
  s.split_share = c.get_double("oo.split_share", d.split_share, 0, 1);
  return s;
}

OOSpec OOSpec::from_config(const Config& c, const OOSpec& m) {
  OOSpec s = parameters(c);
  s.predictor = c.get_bool("oo.predictor", m.predictor);
  s.prealloc = c.get_bool("oo.prealloc", m.prealloc);
  s.split = c.get_bool("oo.split", m.split);
  s.distributed_composition = c.get_choice("oo.composition", m.distributed_composition ? "distributed" : "root",
                                           {"root", "distributed"}) == "distributed";
  s.affinity = c.get_double("oo.affinity", m.affinity, 0, kMaxAffinity);
  return s;
}

OOSettings OOSettings::from_config(const Config& c) {
  OOSettings s;
  s.parameters = OOSpec::parameters(c);
  if (c.has("oo.predictor")) s.predictor = c.get_bool("oo.predictor", true);
  if (c.has("oo.prealloc")) s.prealloc = c.get_bool("oo.prealloc", true);
  if (c.has("oo.split")) s.split = c.get_bool("oo.split", true);
  if (c.has("oo.composition"))
    s.distributed_composition = c.get_choice("oo.composition", "distributed", {"root", "distributed"}) == "distributed";
  if (c.has("oo.affinity")) s.affinity = c.get_double("oo.affinity", 0, 0, kMaxAffinity);
  return s;
}

OOSpec OOSettings::resolve(const OOSpec& m) const {
  OOSpec s = parameters;
  s.predictor = predictor.value_or(m.predictor);
  s.prealloc = prealloc.value_or(m.prealloc);
  s.split = split.value_or(m.split);
  s.distributed_composition = distributed_composition.value_or(m.distributed_composition);
  s.affinity = affinity.value_or(m.affinity);
  return s;
}

void OOSettings::record(const OOSpec& m, std::map<std::string, Config::Entry>& entries) const {
  const OOSpec s = resolve(m);
  const auto entry = [&](const std::string& key, const std::string& value, const std::string& fallback, const std::string& kind) {
    const auto it = entries.find(key);  // given: its source stays
    entries[key] = {value, fallback, it != entries.end() ? it->second.source : "default", kind, "", std::nullopt};
  };
  const auto flag = [](bool b) { return b ? "true" : "false"; };
  entry("oo.predictor", flag(s.predictor), flag(m.predictor), "true or false");
  entry("oo.prealloc", flag(s.prealloc), flag(m.prealloc), "true or false");
  entry("oo.split", flag(s.split), flag(m.split), "true or false");
  const auto composition = [](bool distributed) { return distributed ? "distributed" : "root"; };
  entry("oo.composition", composition(s.distributed_composition), composition(m.distributed_composition),
        "one of root, distributed");
  entry("oo.affinity", format_number(s.affinity), format_number(m.affinity), kAffinityKind);
}

namespace {

// OO-VR's keys: the parameters with their defaults; a switch only when
// given, since its default belongs to the scheme (oo-app: all off, oo-vr:
// all on) and is no machine value.
const std::string kPerScheme = "per scheme: oo-app false, oo-vr true";

const ConfigSections::Add reg(
    "oo",
    {"OO-VR's parameters (Section 5) and mechanism switches",
     nullptr,  // its reader below checks it
     {{"oo.tsl_threshold", "texture sharing level above which objects join a batch (Equation 1, Section 5.1)"},
      {"oo.batch_triangles", "triangles that close a batch (Section 5.1)"},
      {"oo.warmup_batches", "batches dealt round-robin to fit the predictor's c0, c1, c2 (Section 5.2)"},
      {"oo.batch_queue", "batches the distribution engine holds assigned but not started (Section 5.2)"},
      {"oo.tiles_per_unit", "screen tiles of a batch's fragment work per unit, the grain the split moves (assumed)"},
      {"oo.split_share", "share of the busiest GPM's movable leftover units an idle GPM takes when it splits (assumed)"},
      {"oo.predictor", "batches go to the GPM predicted free first (Equation 3), else round-robin", kPerScheme, "true or false"},
      {"oo.prealloc", "pre-allocation units copy a batch's data into its GPM's DRAM ahead of use", kPerScheme, "true or false"},
      {"oo.split", "idle GPMs take the leftover fragment work of large batches, their data copied", kPerScheme, "true or false"},
      {"oo.composition", "root (all colour to GPM 0) or distributed (DHC: N vertical strips, Section 5.3)",
       "per scheme: oo-app root, oo-vr distributed", "one of root, distributed"},
      {"oo.affinity",
       "screen affinity (oovr's, not the paper's): weight of the link time of a batch's pixels owned by other GPMs when the "
       "engine picks its GPM (0: off)",
       "per scheme: oo-vr-affinity 1, the others 0", kAffinityKind}},
     // OO_APP's and OO-VR's own (schemes/impl/oo.cpp names it), read once
     // into the settings they run with.
     true,
     [](const Config& c) { return std::any(OOSettings::from_config(c)); }});

}  // namespace

}  // namespace oovr
