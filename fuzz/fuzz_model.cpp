// libFuzzer target: model files through oovr's loader, checks and assimp
// (formats/model.h): PLY records, GLB chunks, glTF buffers, accessors and
// node graphs, OBJ groups and faces, AC3D objects. The first byte picks the
// format; the rest is the file, read with no other file beside it. Bad
// input must be an Error, never a crash, a hang or an unbounded allocation.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/core/error.h"
#include "oovr/scene/formats/model.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* kNames[] = {"fuzz.ply", "fuzz.glb", "fuzz.gltf", "fuzz.obj", "fuzz.ac"};
  try {
    (void)oovr::load_model_bytes(std::string(reinterpret_cast<const char*>(data) + 1, size - 1), kNames[data[0] % 5]);
  } catch (const oovr::Error&) {
  }
  return 0;
}
