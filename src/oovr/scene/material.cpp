#include "oovr/scene/material.h"

#include <cmath>

namespace oovr {

const char* layer_kind_name(LayerKind k) {
  switch (k) {
    case LayerKind::diffuse: return "diffuse";
    case LayerKind::lightmap: return "lightmap";
    case LayerKind::deluxe: return "deluxe";
    case LayerKind::normal: return "normal";
    case LayerKind::gloss: return "gloss";
    case LayerKind::glow: return "glow";
    case LayerKind::detail: return "detail";
  }
  return "?";
}

const char* shading_name(Shading s) {
  switch (s) {
    case Shading::layers: return "layers";
    case Shading::deluxe: return "deluxe";
  }
  return "?";
}

int Pass::layer(LayerKind k) const {
  for (size_t i = 0; i < layers.size(); ++i)
    if (layers[i].kind == k) return int(i);
  return -1;
}

const char* blend_factor_name(BlendFactor f) {
  switch (f) {
    case BlendFactor::zero: return "zero";
    case BlendFactor::one: return "one";
    case BlendFactor::src_colour: return "src_colour";
    case BlendFactor::one_minus_src_colour: return "one_minus_src_colour";
    case BlendFactor::src_alpha: return "src_alpha";
    case BlendFactor::one_minus_src_alpha: return "one_minus_src_alpha";
    case BlendFactor::dst_colour: return "dst_colour";
    case BlendFactor::one_minus_dst_colour: return "one_minus_dst_colour";
    case BlendFactor::dst_alpha: return "dst_alpha";
    case BlendFactor::one_minus_dst_alpha: return "one_minus_dst_alpha";
  }
  return "?";
}

UvTransform TextureLayer::transform(double seconds) const {
  // Compose in order: each modifier maps the coordinates the earlier ones
  // made (ioquake3's ComputeTexCoords applies them one after another).
  UvTransform m;
  for (const TexMod& mod : mods) {
    if (mod.kind == TexMod::Kind::scale) {
      m = {m.a * mod.s, m.b * mod.s, m.c * mod.s, m.d * mod.t, m.e * mod.t, m.f * mod.t};
    } else {
      // Wrapped to [0, 1) so coordinates stay small over a long run; with
      // a repeating texture this does not change what is sampled.
      const double ds = double(mod.s) * seconds, dt = double(mod.t) * seconds;
      m.c += float(ds - std::floor(ds));
      m.f += float(dt - std::floor(dt));
    }
  }
  return m;
}

namespace {

bool uses_dst(BlendFactor f) {
  return f == BlendFactor::dst_colour || f == BlendFactor::one_minus_dst_colour || f == BlendFactor::dst_alpha ||
         f == BlendFactor::one_minus_dst_alpha;
}

}  // namespace

bool Pass::reads_colour() const { return dst != BlendFactor::zero || uses_dst(src); }

Pass Pass::textured(int diffuse, int lightmap, float lightmap_scale) {
  Pass p;
  if (diffuse >= 0) p.layers.push_back({LayerKind::diffuse, diffuse, TexCoords::surface, Combine::modulate, 1.0f, {}});
  if (lightmap >= 0)
    p.layers.push_back({LayerKind::lightmap, lightmap, TexCoords::lightmap, Combine::modulate, lightmap_scale, {}});
  return p;
}

Material Material::textured(std::string name, int diffuse, int lightmap, float lightmap_scale) {
  Material m;
  m.name = std::move(name);
  m.passes.push_back(Pass::textured(diffuse, lightmap, lightmap_scale));
  return m;
}

}  // namespace oovr
