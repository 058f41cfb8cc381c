// libFuzzer target: the TORCS track description reader (pugixml, then the
// segments walked into a centre line). Bad input must be an Error; a line
// it returns must be finite and bounded.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/core/error.h"
#include "oovr/scene/sources/torcs.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const auto line = oovr::torcs_centre_line_from_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.xml");
    if (line.size() > 2000000) __builtin_trap();
    for (const oovr::Vec3& p : line)
      if (!std::isfinite(p.x) || !std::isfinite(p.z)) __builtin_trap();
  } catch (const oovr::Error&) {
  }
  return 0;
}
