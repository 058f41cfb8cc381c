#include "oovr/pipeline/shader_cost.h"

namespace oovr {

uint32_t fragment_instructions(const Pass& pass) {
  using C = FragmentCosts;
  uint32_t n = C::setup + C::output;
  const bool lit = pass.shading == Shading::deluxe;
  if (lit) {
    n += C::lit_varyings + C::light_direction + C::light_colour + C::diffuse_light;
    if (pass.layer(LayerKind::normal) >= 0) n += C::surface_normal;
    if (pass.layer(LayerKind::gloss) >= 0) n += C::specular;
    if (pass.layer(LayerKind::glow) >= 0) n += C::glow;
  }
  for (size_t i = 0; i < pass.layers.size(); ++i) {
    const TextureLayer& l = pass.layers[i];
    n += C::coordinates + C::lookup;
    // A static or a moving transform costs the same; only modifiers that
    // do nothing are free (the compiler drops them).
    bool transformed = false;
    for (const TexMod& m : l.mods)
      transformed = transformed || (m.kind == TexMod::Kind::scale ? (m.s != 1 || m.t != 1) : (m.s != 0 || m.t != 0));
    if (transformed) n += C::transform;
    if (l.scale != 1.0f) n += C::scale;
    if (l.combine == Combine::fetch) {
      // A captured program's texture oovr samples but does not draw with:
      // what the program computes with it, as per-pixel lighting's terms.
      if (!lit && l.kind == LayerKind::normal) n += C::surface_normal + C::diffuse_light;
      if (!lit && l.kind == LayerKind::gloss) n += C::specular;
      continue;
    }
    if (i > 0 && !lit) n += C::combine;  // a lit pass combines its layers through the lighting above
  }
  const Vec4& c = pass.colour;
  if (!(c.x == 1 && c.y == 1 && c.z == 1 && c.w == 1)) n += C::colour;
  if (pass.alpha_tested()) n += C::alpha_test;
  return n;
}

}  // namespace oovr
