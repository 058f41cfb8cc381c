// libFuzzer target: the checks that stand between a model file and assimp
// (PLY records, GLB chunks, glTF buffers and accessors). The first byte
// picks the format; bad input must be an Error, never a crash or a hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/core/error.h"
#include "oovr/scene/formats/model_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* kNames[] = {"fuzz.ply", "fuzz.glb", "fuzz.gltf"};
  try {
    oovr::precheck_model_bytes(std::string(reinterpret_cast<const char*>(data) + 1, size - 1), kNames[data[0] % 3]);
  } catch (const oovr::Error&) {
  }
  return 0;
}
