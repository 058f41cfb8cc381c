// libFuzzer target: oovr's AC3D reader (TORCS tracks and cars). Bad input
// must be an Error; a scene it returns must validate.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/core/error.h"
#include "oovr/scene/formats/ac3d.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    oovr::Ac3dOptions options;
    const oovr::Scene s =
        oovr::parse_ac3d(std::string(reinterpret_cast<const char*>(data), size), "/nonexistent/fuzz.ac", options);
    s.validate();
  } catch (const oovr::Error&) {
  }
  return 0;
}
