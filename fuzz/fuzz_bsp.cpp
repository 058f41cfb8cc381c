// libFuzzer target: the Quake 3 BSP parser and patch tessellation. Any input
// must give a parsed map or an oovr::Error, never a crash, a sanitizer report
// or an unbounded allocation.
#include <cstddef>
#include <cstdint>

#include "oovr/core/error.h"
#include "oovr/scene/formats/bsp.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const oovr::BspMap map = oovr::parse_bsp(data, size, "fuzz.bsp");
    std::vector<oovr::BspVertex> vertices;
    std::vector<uint32_t> indices;
    for (const auto& face : map.faces) {
      vertices.clear();
      indices.clear();
      oovr::bsp_face_triangles(map, face, 3, vertices, indices);
      for (uint32_t i : indices)
        if (i >= vertices.size()) __builtin_trap();  // an index past the vertices is a bug
    }
  } catch (const oovr::Error&) {
  }
  return 0;
}
