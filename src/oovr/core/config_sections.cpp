#include "oovr/core/config_sections.h"

namespace oovr {

void check_config(const Config& c) {
  for (const auto& name : ConfigSections::names()) ConfigSections::find(name)->check(c);
  c.check_all_used();
}

}  // namespace oovr
