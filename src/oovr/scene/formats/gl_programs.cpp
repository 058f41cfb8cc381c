#include "oovr/scene/formats/gl_programs.h"

#include <sstream>

#include "oovr/core/error.h"

namespace oovr {

std::set<std::string> permutation_defines(const std::vector<std::string>& source_strings) {
  std::set<std::string> out;
  for (size_t i = 0; i + 1 < source_strings.size(); ++i) {
    std::istringstream lines(source_strings[i]);
    std::string line;
    while (std::getline(lines, line)) {
      std::istringstream words(line);
      std::string directive, name;
      words >> directive >> name;
      if (directive == "#define" && !name.empty()) out.insert(name);
    }
  }
  return out;
}

namespace {

// Defines that change nothing oovr draws: the GLSL dialect, the stage, and
// features whose effect is outside the fragment's colour.
bool neutral(const std::string& d) {
  static const std::set<std::string> names = {"GLSL120", "GLSL130", "GLSL140", "GLSL150", "GLES", "VERTEX_SHADER",
                                              "FRAGMENT_SHADER", "GEOMETRY_SHADER",
                                              // The vertex colour's alpha as the fragment's (read below).
                                              "USEALPHAGENVERTEX"};
  return names.count(d) > 0;
}

}  // namespace

const std::vector<SamplerKind>& darkplaces_2d_samplers() {
  // Not the cube maps (Texture_Cube, Texture_ReflectCube,
  // Texture_CubeProjection), the 3-D bounce grid or the shadow map, which
  // the permutations oovr draws do not read.
  using K = LayerKind;
  static const std::vector<SamplerKind> names = {{"Texture_First", K::diffuse},
                                                 {"Texture_Second", K::diffuse},
                                                 {"Texture_Color", K::diffuse},
                                                 {"Texture_Lightmap", K::lightmap},
                                                 {"Texture_Deluxemap", K::deluxe},
                                                 {"Texture_Normal", K::normal},
                                                 {"Texture_Gloss", K::gloss},
                                                 {"Texture_Glow", K::glow},
                                                 {"Texture_Pants", K::diffuse},
                                                 {"Texture_Shirt", K::diffuse},
                                                 {"Texture_SecondaryColor", K::diffuse},
                                                 {"Texture_SecondaryNormal", K::normal},
                                                 {"Texture_SecondaryGloss", K::gloss},
                                                 {"Texture_SecondaryGlow", K::glow},
                                                 {"Texture_Attenuation", K::diffuse},
                                                 {"Texture_FogMask", K::diffuse},
                                                 {"Texture_FogHeightTexture", K::diffuse},
                                                 {"Texture_ReflectMask", K::diffuse}};
  return names;
}

// DarkPlaces' shader (shader_glsl.h, 2018): gl_Position is
// ModelViewProjectionMatrix * Attrib_Position in every mode; the surface's
// coordinates are TexMatrix * Attrib_TexCoord0, the lightmap's
// Attrib_TexCoord4, a generic draw's second texture's Attrib_TexCoord1.
ProgramRecipe darkplaces_recipe(const std::set<std::string>& defines) {
  ProgramRecipe r;
  for (const auto& d : defines)
    if (d.rfind("MODE_", 0) == 0) {
      if (!r.mode.empty()) throw Error("DarkPlaces programs of two modes (" + r.mode + " and " + d + ")");
      r.mode = d;
    }
  if (r.mode.empty()) throw Error("programs without a DarkPlaces MODE_ define (not DarkPlaces' shader)");
  const auto has = [&](const char* d) { return defines.count(d) > 0; };
  r.position = "Attrib_Position";
  r.mvp = "ModelViewProjectionMatrix";
  std::set<std::string> read;  // the defines this recipe takes into account
  read.insert(r.mode);
  const auto use = [&](const char* d) {
    read.insert(d);
    return has(d);
  };
  if (r.mode == "MODE_GENERIC") {
    // dp_FragColor = VertexColor (USEVIEWTINT, as DarkPlaces names it
    // here; else white) * Texture_First; then the second texture modulates
    // (USECOLORMAPPING) or adds (USEGLOW).
    if (use("USEVIEWTINT")) r.colour = "Attrib_Color";
    if (use("USEALPHAKILL")) r.alpha = "Alpha";  // dp_FragColor.a *= Alpha
    if (use("USEDIFFUSE")) {
      r.uv = "Attrib_TexCoord0";
      r.layers.push_back({"Texture_First", TexCoords::surface, Combine::modulate, "", false});
    }
    if (use("USESPECULAR")) {
      r.lightmap_uv = "Attrib_TexCoord1";
      const bool modulate = use("USECOLORMAPPING"), add = use("USEGLOW");
      if (modulate == add || use("USEVERTEXTEXTUREBLEND"))
        throw Error("DarkPlaces' generic programs combining a second texture otherwise than by one product or one sum");
      if (r.layers.empty()) throw Error("DarkPlaces' generic programs with a second texture and no first");
      r.layers.push_back({"Texture_Second", TexCoords::lightmap, add ? Combine::add : Combine::modulate, "", false});
    }
  } else if (r.mode == "MODE_POSTPROCESS") {
    // The view's texture (Texture_First) into the window, mixed with
    // ViewTintColor by its alpha (USEVIEWTINT) and saturated (USESATURATION).
    r.uv = "Attrib_TexCoord0";
    r.composite = true;
    r.layers.push_back({"Texture_First", TexCoords::surface, Combine::modulate, "", false});
    if (use("USEVIEWTINT")) r.identity_when.push_back({"ViewTintColor", 3, 0.0f});
    if (use("USESATURATION")) r.identity_when.push_back({"Saturation", 0, 1.0f});
    // Gamma through a 256-texel ramp texture (v_glslgamma_video): a copy
    // while the ramp maps each level to itself (v_gamma 1, v_contrast 1).
    if (use("USEGAMMARAMPS")) r.gamma_ramps = "Texture_GammaRamps";
  } else if (r.mode == "MODE_DEPTH_OR_SHADOW") {
    r.depth_only = true;
  } else if (r.mode == "MODE_LIGHTMAP" || r.mode == "MODE_VERTEXCOLOR" || r.mode == "MODE_FLATCOLOR" ||
             r.mode == "MODE_LIGHTDIRECTION" || r.mode == "MODE_FAKELIGHT") {
    // color = Texture_Color x Alpha, then RGB: Texture_Color x (Color_Ambient
    // + light x Color_Diffuse), light the lightmap's texel (MODE_LIGHTMAP),
    // the vertex colour (MODE_VERTEXCOLOR), none (MODE_FLATCOLOR), or the
    // diffuse term of a light direction (MODE_LIGHTDIRECTION, models); then
    // + Texture_Glow x Color_Glow (USEGLOW).
    r.uv = "Attrib_TexCoord0";
    r.tex_matrix = "TexMatrix";
    r.alpha = "Alpha";
    r.alpha_kill = use("USEALPHAKILL");
    r.layers.push_back({"Texture_Color", TexCoords::surface, Combine::modulate, "", false});
    if (r.mode == "MODE_LIGHTMAP") {
      r.lightmap_uv = "Attrib_TexCoord4";
      r.layers.push_back({"Texture_Lightmap", TexCoords::lightmap, Combine::modulate, "", false});
      r.colour_rgb = "Color_Diffuse";
      r.ambient = "Color_Ambient";
    } else if (r.mode == "MODE_VERTEXCOLOR") {
      r.colour = "Attrib_Color";
      r.colour_rgb = "Color_Diffuse";
      r.ambient = "Color_Ambient";
    } else if (r.mode == "MODE_FLATCOLOR") {
      r.colour_rgb = "Color_Ambient";
    } else if (r.mode == "MODE_LIGHTDIRECTION") {
      // Ambient + diffuse x max(0, N.L) per fragment from the normal map;
      // here per vertex from the vertex normal (Attrib_TexCoord3), the
      // normal map and any specular left out.
      if (use("USEDIFFUSE")) {
        r.light_dir = "LightDir";
        r.normal = "Attrib_TexCoord3";
        r.light_diffuse = "Color_Diffuse";
      }
      r.light_ambient = "Color_Ambient";
      r.approximation =
          use("USESPECULAR") ? "lit per vertex, without the normal map or specular" : "lit per vertex, without the normal map";
      read.insert("USENORMALMAPSCROLLBLEND");
    } else {
      // MODE_FAKELIGHT: a light at the eye; taken whole.
      r.colour_rgb = "Color_Diffuse";
      r.approximation = "lit by Color_Diffuse whole, without the light's direction, Color_Ambient or specular";
      read.insert({"USEDIFFUSE", "USESPECULAR", "USENORMALMAPSCROLLBLEND"});
    }
    if (use("USECOLORMAPPING")) {
      // Player colours: color.rgb += Texture_Pants x Color_Pants +
      // Texture_Shirt x Color_Shirt, before the light; added here after it,
      // untinted.
      r.layers.push_back({"Texture_Pants", TexCoords::surface, Combine::add, "Color_Pants", true});
      r.layers.push_back({"Texture_Shirt", TexCoords::surface, Combine::add, "Color_Shirt", true});
      r.approximation +=
          std::string(r.approximation.empty() ? "" : "; ") + "pants and shirt added after the light, tinted and lit grey";
    }
    if (use("USEGLOW")) r.layers.push_back({"Texture_Glow", TexCoords::surface, Combine::add, "Color_Glow", false});
    if (use("USEALPHAGENVERTEX")) r.colour = "Attrib_Color";
    // Gloss lights only lit modes (SHADING); a lightmap's is unused.
    if (r.mode != "MODE_LIGHTDIRECTION" && r.mode != "MODE_FAKELIGHT") read.insert("USESPECULAR");
  } else {
    throw Error("DarkPlaces' " + r.mode + " programs");
  }
  // Shadow-map filtering options do nothing without a shadow map to filter.
  if (!has("USESHADOWMAP2D") && !has("USESHADOWMAPORTHO"))
    read.insert({"USESHADOWMAPPCF", "USESHADOWSAMPLER", "USESHADOWMAPVSDCT"});
  for (const auto& d : defines)
    if (!read.count(d) && !neutral(d)) throw Error("DarkPlaces' " + r.mode + " programs with " + d);
  return r;
}

}  // namespace oovr
