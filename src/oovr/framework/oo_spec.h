// OO-VR's parameters and mechanism switches, from the configuration.
//
// Parameters (in configs/paper-table1.toml, values from Section 5):
//   oo.tsl_threshold   texture sharing level above which objects batch (0.5)
//   oo.batch_triangles triangles that close a batch (4096)
//   oo.warmup_batches  batches dealt round-robin to fit the predictor (8)
//   oo.batch_queue     batches the engine holds assigned but not started (4)
//   oo.tiles_per_unit  screen tiles of a batch's fragment work per work unit,
//                      the grain the fine-grained split moves (32, assumed)
//   oo.split_share     share of the busiest GPM's movable leftovers an idle
//                      GPM takes when it splits (0.5, assumed)
// Mechanisms, each a switch so that ablations can measure it (the scheme
// sets its own defaults: oo-app all off, oo-vr all on):
//   oo.predictor   batches go to the GPM predicted free first (else round-robin)
//   oo.prealloc    pre-allocation units copy a batch's data to its GPM ahead of use
//   oo.split       leftover work of large batches is split over idle GPMs
//   oo.composition "root" (all colour to GPM 0) or "distributed" (DHC: N
//                  vertical strips, each composed by its owner's ROPs)
//   oo.affinity    screen affinity, oovr's own and not the paper's (0: off,
//                  the paper's engine): the engine sends a batch to the GPM
//                  for which its predicted free time plus this weight times
//                  the link time of the batch's pixels owned by other GPMs
//                  (as its objects' pixels fell in the previous frame) is
//                  least (framework/runtime.h)
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "oovr/core/config.h"

namespace oovr {

struct OOSpec {
  double tsl_threshold = 0.5;
  int batch_triangles = 4096;
  int warmup_batches = 8;
  int batch_queue = 4;
  int tiles_per_unit = 32;
  double split_share = 0.5;
  bool predictor = true;
  bool prealloc = true;
  bool split = true;
  bool distributed_composition = true;
  double affinity = 0;

  // `mechanisms` gives the switches' defaults (the scheme's own).
  static OOSpec from_config(const Config& c, const OOSpec& mechanisms);
  // The parameters alone (the machine-wide keys a preset holds). The keys
  // are declared, and checked whatever scheme runs, by this file's
  // configuration section (core/config_sections.h).
  static OOSpec parameters(const Config& c);
};

// OO-VR's section as a run reads it, once (MachineSpec::own("oo")): the
// parameters, and each switch as given (the scheme gives the rest).
struct OOSettings {
  OOSpec parameters;
  std::optional<bool> predictor, prealloc, split;
  std::optional<bool> distributed_composition;
  std::optional<double> affinity;

  static OOSettings from_config(const Config& c);
  // The spec a scheme whose switches default to `mechanisms` runs.
  OOSpec resolve(const OOSpec& mechanisms) const;
  // Describes the switches in `entries` as that scheme reads them: the
  // value in force and the scheme's default, as Config::entries would.
  void record(const OOSpec& mechanisms, std::map<std::string, Config::Entry>& entries) const;
};

}  // namespace oovr
