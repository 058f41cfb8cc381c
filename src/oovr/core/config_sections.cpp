#include "oovr/core/config_sections.h"

namespace oovr {

const ConfigKey* find_config_key(const std::string& key) {
  for (const auto& name : ConfigSections::names())
    for (const ConfigKey& k : ConfigSections::find(name)->keys)
      if (k.key == key) return &k;
  return nullptr;
}

std::string config_section_of(const std::string& key) {
  for (const auto& name : ConfigSections::names())
    for (const ConfigKey& k : ConfigSections::find(name)->keys)
      if (k.key == key) return name;
  return "";
}

void check_config(const Config& c, const std::set<std::string>& already_read) {
  for (const auto& name : ConfigSections::names()) {
    if (already_read.count(name)) continue;
    const ConfigSection& s = *ConfigSections::find(name);
    if (s.read) (void)s.read(c);
    else s.check(c);
  }
  c.check_all_used();
  // A key a component reads is one a user can set: it must be listed, with
  // its meaning, by the section that reads it.
  for (const auto& [key, entry] : c.entries())
    if (!find_config_key(key))
      throw Error("configuration key '" + key +
                  "' is read but no configuration section declares it (core/config_sections.h): an oovr defect");
}

}  // namespace oovr
