// libFuzzer target: the configuration reader (TOML through toml++, after
// oovr's shape check) and every component that reads the keys. Bad input
// must be an Error, never a crash, a hang or an unbounded allocation.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/core/config.h"
#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const oovr::Config c = oovr::Config::from_toml_string(std::string(reinterpret_cast<const char*>(data), size), "fuzz.toml");
    oovr::check_config(c);
    // Whatever was read, its printed form reads back.
    oovr::Config back;
    for (const auto& [key, value] : c.resolved()) back.set(key, value);
    oovr::check_config(back);
    if (back.resolved() != c.resolved()) __builtin_trap();
  } catch (const oovr::Error&) {
  }
  return 0;
}
