// libFuzzer target: the Quake 3 shader script parser and the passes built
// from what it read. Parsing never throws (problems become notes); every
// shader must turn into at least one pass whose layers name only the
// textures the lookup handed out, with every enum in range.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/scene/formats/q3_shader.h"

namespace {

struct Lookup : oovr::Q3TextureLookup {
  int lm;
  explicit Lookup(int lightmap) : lm(lightmap) {}
  int image(const oovr::Q3Stage&) override { return 0; }
  int lightmap() override { return lm; }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  oovr::Q3ShaderSet set;
  oovr::parse_q3_shader_script(std::string(reinterpret_cast<const char*>(data), size), "fuzz.shader", set);
  for (const auto& [name, shader] : set.shaders)
    for (int lm : {-1, 1}) {
      Lookup lookup(lm);
      const oovr::Q3Passes q = oovr::q3_passes(&shader, lookup);
      if (q.passes.empty()) __builtin_trap();
      for (const oovr::Pass& p : q.passes) {
        if (p.layers.size() > shader.stages.size() + 1) __builtin_trap();
        if (int(p.src) > int(oovr::BlendFactor::one_minus_dst_alpha) || int(p.dst) > int(oovr::BlendFactor::one_minus_dst_alpha))
          __builtin_trap();
        for (const oovr::TextureLayer& l : p.layers)
          if (l.texture != 0 && l.texture != lm) __builtin_trap();
      }
    }
  return 0;
}
