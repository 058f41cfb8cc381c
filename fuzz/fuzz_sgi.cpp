// libFuzzer target: the SGI image decoder. Any input must give an image of
// the size its header states or an oovr::Error.
#include <cstddef>
#include <cstdint>

#include "oovr/core/error.h"
#include "oovr/scene/texture.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const oovr::MipLevel l = oovr::decode_sgi(data, size, "fuzz.rgb");
    if (l.rgba.size() != size_t(l.width) * size_t(l.height) * 4) __builtin_trap();
  } catch (const oovr::Error&) {
  }
  return 0;
}
