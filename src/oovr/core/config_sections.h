// Configuration sections: every component that reads configuration keys
// declares them in its own file, with the check that reads (and so
// validates) them and a one-line meaning for each key:
//
//   const ConfigSections::Add reg("memory", {"...", [](const Config& c) { (void)MemorySpec::from_config(c); },
//                                            {{"gpms", "GPU modules (GPMs) of the machine"}, ...}});
//
// check_config() runs every section's check, then reports each key that no
// section read as unknown (as pbrt-v4 reports unused parameters and
// Ramulator 2 rejects undeclared ones), and refuses a key read that no
// section declares, so that `oovr config --all` lists everything a user
// can set with what it means. So a component's keys are known and
// their values checked whatever runs (`oovr compare --set oo.split=false`
// runs the baseline too), and no shared code names another component's keys:
// a scheme with settings of its own is one file.
#pragma once

#include <any>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/core/registry.h"

namespace oovr {

// One key a section reads.
struct ConfigKey {
  std::string key;
  std::string meaning;  // one line: what it sets, with its source where it has one
  // For a key whose default belongs to whoever uses it (OO-VR's switches:
  // each scheme's own) and which the check reads only when given: that
  // default, and what the key takes, as `oovr config --all` shows them.
  std::string user_default = {};
  std::string takes = {};
};

struct ConfigSection {
  std::string description;
  // Reads the section's keys (defaults for absent ones, except where a
  // default belongs to whoever uses the key); throws Error on a bad value.
  std::function<void(const Config&)> check;
  std::vector<ConfigKey> keys;  // every key `check` reads
  // A scheme's own section (OO-VR's `oo`): only the schemes that name it in
  // their registration (SchemeFactory::sections) read it, and a run of any
  // other scheme neither records its keys nor hashes them into its id, so
  // adding a scheme with keys of its own changes no stored run. Every
  // other section is the machine's.
  bool scheme_section = false;
  // For a scheme's own section: reads its keys once into the settings its
  // schemes use (MachineSpec::own), instead of `check`.
  std::function<std::any(const Config&)> read = {};
};
using ConfigSections = Registry<ConfigSection>;

// Runs every section's check (its reader, when it has one), then throws
// Error naming every key no section read, or one that was read but that no
// section declares. Afterwards c.resolved() holds every value in force.
// Sections named in `already_read` are taken as read (MachineSpec reads
// those into typed fields itself).
void check_config(const Config& c, const std::set<std::string>& already_read = {});

// The declaration of `key` (null when no section declares it).
const ConfigKey* find_config_key(const std::string& key);
// The name of the section declaring `key` ("" when none does).
std::string config_section_of(const std::string& key);

}  // namespace oovr
