// Materials: how a surface is drawn, as its engine draws it.
//
// A material is an ordered list of passes. A pass is one draw of the
// surface: it samples one or more texture layers (diffuse, lightmap,
// deluxe, normal, gloss, glow, detail), combines them into a colour and
// writes that colour through its blend function, alpha function and depth
// state. A Quake 3 shader whose stages cannot be merged into one
// multitexture pass is several passes (ioquake3's CollapseMultitexture); a
// DarkPlaces surface with normal, gloss and deluxe maps is one pass that
// samples all of them.
//
// Every object (draw) of a scene draws one pass of its material
// (Object::pass); Scene::add_draws makes one object per pass, in order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oovr/core/math.h"

namespace oovr {

// What a texture layer holds; decides how the shading combines it.
enum class LayerKind : uint8_t { diffuse, lightmap, deluxe, normal, gloss, glow, detail };
const char* layer_kind_name(LayerKind k);

// Which vertex coordinates a layer samples with.
enum class TexCoords : uint8_t { surface, lightmap };

// A texture-coordinate transform (Quake 3's tcMod), applied in order to
// the layer's coordinates: scale multiplies them, scroll adds `speed x
// seconds`, wrapped to [0, 1) as ioquake3's RB_CalcScrollTexCoords does.
struct TexMod {
  enum class Kind : uint8_t { scale, scroll };
  Kind kind = Kind::scale;
  float s = 1, t = 1;
};

// The affine map a layer's modifiers make at one moment:
// s' = a*s + b*t + c, t' = d*s + e*t + f.
struct UvTransform {
  float a = 1, b = 0, c = 0, d = 0, e = 1, f = 0;
  bool identity() const { return a == 1 && b == 0 && c == 0 && d == 0 && e == 1 && f == 0; }
};

// How a layer's texel joins the colour made so far (the first layer's
// texel is the starting colour, then multiplied by the pass colour):
// modulate multiplies RGBA (an RGB scale, e.g. a lightmap's overbright
// factor, applies to the texel's RGB); add adds the texel's RGB x scale
// (fixed function's GL_ADD for RGB; alpha still multiplies); replace, on
// the first layer only, takes the texel as it is: neither the pass colour
// nor the vertex colours multiply it (fixed function's GL_REPLACE); fetch
// samples the texel and leaves the colour as it is: a texture a captured
// game's shader reads for what oovr does not draw (a lit model's normal and
// gloss maps), so that its fetches and memory traffic are counted.
enum class Combine : uint8_t { modulate, add, replace, fetch };

struct TextureLayer {
  LayerKind kind = LayerKind::diffuse;
  int texture = -1;  // index into Scene::textures
  TexCoords coords = TexCoords::surface;
  Combine combine = Combine::modulate;
  float scale = 1.0f;  // RGB factor of the texel
  std::vector<TexMod> mods;

  UvTransform transform(double seconds) const;
};

// Fixed-function blending (dst = src x src_factor + dst x dst_factor).
enum class BlendFactor : uint8_t {
  zero,
  one,
  src_colour,
  one_minus_src_colour,
  src_alpha,
  one_minus_src_alpha,
  dst_colour,
  one_minus_dst_colour,
  dst_alpha,
  one_minus_dst_alpha
};
const char* blend_factor_name(BlendFactor f);

// Alpha test: a fragment survives when `alpha FUNC reference`
// (Quake 3's GT0 = greater 0, LT128 = less 0.5, GE128 = gequal 0.5).
enum class AlphaFunc : uint8_t { always, greater, less, gequal };

// Depth test: a fragment passes when its depth is FUNC the stored one.
enum class DepthFunc : uint8_t { less, lequal, equal, always };

// How a pass turns its layers into a colour.
//  - layers: the layers combined in order (see Combine), times the pass
//    colour; fixed-function multitexture.
//  - deluxe: DarkPlaces' per-pixel lighting from a lightmap and a deluxe
//    map of model-space light directions (its GLSL shader's
//    MODE_LIGHTDIRECTIONMAP_MODELSPACE, for maps compiled with q3map2
//    -deluxe). With D the diffuse texel, N = normalize(normal texel - 0.5)
//    (0,0,1 without a normal layer), L the deluxe direction taken into the
//    surface's tangent frame (S, T, N of Mesh::frames) and normalised, C the
//    lightmap texel x scale / max(0.25, L.z) (undoing the cosine the
//    lightmap already holds), E the normalised tangent-space direction to
//    the eye and H = normalize(L + E):
//      rgb = D.rgb x max(N.L, 0) x C
//          + G.rgb x specular_intensity x pow(max(N.H, 0), specular_power x G.a) x C   (with a gloss layer G)
//          + glow.rgb                                                                 (with a glow layer)
//      a   = D.a; both then times the pass colour.
//    Layers are found by kind; diffuse, lightmap and deluxe are required.
enum class Shading : uint8_t { layers, deluxe };
const char* shading_name(Shading s);

struct Pass {
  std::vector<TextureLayer> layers;  // may be empty: the pass colour alone
  Shading shading = Shading::layers;
  Vec4 colour{1, 1, 1, 1};  // RGBA multiplier (Quake 3's rgbGen/alphaGen const), linear 0..1
  BlendFactor src = BlendFactor::one, dst = BlendFactor::zero;
  AlphaFunc alpha_func = AlphaFunc::always;
  float alpha_ref = 0.5f;
  DepthFunc depth_func = DepthFunc::less;
  bool depth_write = true;
  bool colour_write = true;  // glColorMask: false writes depth only (a captured game's depth clear)
  // Shading::deluxe's specular term: DarkPlaces' r_shadow_glossexponent and
  // r_shadow_glossintensity defaults.
  float specular_power = 32.0f, specular_intensity = 1.0f;
  // glPolygonOffset: depth moved by factor x the triangle's largest depth
  // slope + units x the depth buffer's resolution (decals over walls).
  float offset_factor = 0, offset_units = 0;

  // The index of the first layer of kind `k`, or -1.
  int layer(LayerKind k) const;

  // A pass whose colour depends on what is already in the frame reads it.
  bool reads_colour() const;
  bool blended() const { return !(src == BlendFactor::one && dst == BlendFactor::zero); }
  bool alpha_tested() const { return alpha_func != AlphaFunc::always; }

  // One opaque pass: diffuse (when >= 0) x lightmap (when >= 0, its RGB
  // scaled by lightmap_scale), the classic lightmapped surface.
  static Pass textured(int diffuse, int lightmap = -1, float lightmap_scale = 1.0f);
};

struct Material {
  std::string name;
  std::vector<Pass> passes;  // drawn in order; at least one
  bool two_sided = false;    // no back-face culling
  bool cull_front = false;   // cull front faces instead (glCullFace(GL_FRONT)); unless two_sided

  // A one-pass material (Pass::textured).
  static Material textured(std::string name, int diffuse, int lightmap = -1, float lightmap_scale = 1.0f);
  Pass& pass() { return passes.front(); }
  const Pass& pass() const { return passes.front(); }
};

}  // namespace oovr
