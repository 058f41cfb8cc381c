#include "oovr/framework/oo_spec.h"

#include <string>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"

namespace oovr {

OOSpec OOSpec::parameters(const Config& c) {
  OOSpec s;
  const OOSpec d;
  s.tsl_threshold = c.get_double("oo.tsl_threshold", d.tsl_threshold, 0, 1);
  const auto positive = [&](const char* key, int def, int max) { return int(c.get_int(key, def, 1, max)); };
  s.batch_triangles = positive("oo.batch_triangles", d.batch_triangles, 1 << 30);
  s.warmup_batches = positive("oo.warmup_batches", d.warmup_batches, 1 << 20);
  s.batch_queue = positive("oo.batch_queue", d.batch_queue, 1 << 20);
  s.tiles_per_unit = positive("oo.tiles_per_unit", d.tiles_per_unit, 1 << 20);
  return s;
}

OOSpec OOSpec::from_config(const Config& c, const OOSpec& m) {
  OOSpec s = parameters(c);
  s.predictor = c.get_bool("oo.predictor", m.predictor);
  s.prealloc = c.get_bool("oo.prealloc", m.prealloc);
  s.split = c.get_bool("oo.split", m.split);
  s.distributed_composition = c.get_choice("oo.composition", m.distributed_composition ? "distributed" : "root",
                                           {"root", "distributed"}) == "distributed";
  return s;
}

namespace {

// OO-VR's keys: the parameters with their defaults; a switch only when
// given, since its default belongs to the scheme (oo-app: all off, oo-vr:
// all on) and is no machine value.
const std::string kPerScheme = "per scheme: oo-app false, oo-vr true";

const ConfigSections::Add reg(
    "oo",
    {"OO-VR's parameters (Section 5) and mechanism switches",
     [](const Config& c) {
       (void)OOSpec::parameters(c);
       for (const char* k : {"oo.predictor", "oo.prealloc", "oo.split"})
         if (c.has(k)) (void)c.get_bool(k, true);
       if (c.has("oo.composition")) (void)c.get_choice("oo.composition", "distributed", {"root", "distributed"});
     },
     {{"oo.tsl_threshold", "texture sharing level above which objects join a batch (Equation 1, Section 5.1)"},
      {"oo.batch_triangles", "triangles that close a batch (Section 5.1)"},
      {"oo.warmup_batches", "batches dealt round-robin to fit the predictor's c0, c1, c2 (Section 5.2)"},
      {"oo.batch_queue", "batches the distribution engine holds assigned but not started (Section 5.2)"},
      {"oo.tiles_per_unit", "screen tiles of a batch's fragment work per unit, the grain the split moves (assumed)"},
      {"oo.predictor", "batches go to the GPM predicted free first (Equation 3), else round-robin", kPerScheme, "true or false"},
      {"oo.prealloc", "pre-allocation units copy a batch's data into its GPM's DRAM ahead of use", kPerScheme, "true or false"},
      {"oo.split", "idle GPMs take the leftover fragment work of large batches, their data copied", kPerScheme, "true or false"},
      {"oo.composition", "root (all colour to GPM 0) or distributed (DHC: N vertical strips, Section 5.3)",
       "per scheme: oo-app root, oo-vr distributed", "one of root, distributed"}},
     // OO_APP's and OO-VR's own (schemes/impl/oo.cpp names it).
     true});

}  // namespace

}  // namespace oovr
