// Configuration sections: every component that reads configuration keys
// declares them in its own file, with the check that reads (and so
// validates) them:
//
//   const ConfigSections::Add reg("memory", {"...", [](const Config& c) { (void)MemorySpec::from_config(c); }});
//
// check_config() runs every section's check, then reports each key that no
// section read as unknown (as pbrt-v4 reports unused parameters and
// Ramulator 2 rejects undeclared ones). So a component's keys are known and
// their values checked whatever runs (`oovr compare --set oo.split=false`
// runs the baseline too), and no shared code names another component's keys:
// a scheme with settings of its own is one file.
#pragma once

#include <functional>
#include <string>

#include "oovr/core/config.h"
#include "oovr/core/registry.h"

namespace oovr {

struct ConfigSection {
  std::string description;
  // Reads the section's keys (defaults for absent ones, except where a
  // default belongs to whoever uses the key); throws Error on a bad value.
  std::function<void(const Config&)> check;
};
using ConfigSections = Registry<ConfigSection>;

// Runs every section's check, then throws Error naming every key no section
// read. Afterwards c.resolved() holds every value in force.
void check_config(const Config& c);

}  // namespace oovr
