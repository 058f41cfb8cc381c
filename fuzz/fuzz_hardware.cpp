// libFuzzer target: the hardware data reader (experiments/hardware.h, the
// CSV `oovr correlate` reads). Any input is data or one oovr::Error; data
// written back reads back as the same text.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/core/error.h"
#include "oovr/experiments/hardware.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const oovr::HardwareData d = oovr::HardwareData::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.csv");
    const std::string text = d.csv();
    if (oovr::HardwareData::parse(text, "again.csv").csv() != text) __builtin_trap();
  } catch (const oovr::Error&) {
  }
  return 0;
}
