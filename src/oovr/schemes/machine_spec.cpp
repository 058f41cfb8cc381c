#include "oovr/schemes/machine_spec.h"

#include <set>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"

namespace oovr {

MachineSpec MachineSpec::from_config(const Config& c) {
  MachineSpec m;
  m.config = c;
  const Config& r = m.config;  // reading marks keys used in this copy
  m.memory = MemorySpec::from_config(r);
  m.timing = TimingSpec::from_config(r);
  m.composition = CompositionSpec::from_config(r);
  m.pipeline = PipelineSettings::from_config(r);
  // The other sections, each read once: a scheme's own into own(), the
  // rest checked; then every key must have been read and declared.
  std::set<std::string> read = {"memory", "timing", "composition", "pipeline"};
  for (const auto& name : ConfigSections::names()) {
    if (read.count(name)) continue;
    const ConfigSection& s = *ConfigSections::find(name);
    if (s.read) m.m_own[name] = s.read(r);
    else s.check(r);
    read.insert(name);
  }
  check_config(r, read);
  m.entries = r.entries();
  return m;
}

void MachineSpec::set_entry(const std::string& key, std::string value, std::optional<double> base) {
  Config::Entry& e = entries[key];
  e.value = std::move(value);
  e.base = base;
  e.source = m_source;
}

void MachineSpec::throw_missing(const std::string& section) {
  throw Error("configuration section '" + section + "' has no settings of its own in this machine (no reader registered)");
}

}  // namespace oovr
