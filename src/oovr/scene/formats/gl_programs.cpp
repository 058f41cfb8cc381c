#include "oovr/scene/formats/gl_programs.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
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

namespace oovr {

// ---- ioquake3's opengl2 renderer (renderergl2) ----

namespace {

// A shader's source split at ioquake3's `#line 0`: the header it prepends
// (version, compatibility macros, the constants' and the permutation's
// #defines) and the body (glsl/*.glsl).
struct Ioq3Source {
  std::string header, body;
};

bool split_ioq3(const std::vector<std::string>& strings, Ioq3Source& out) {
  std::string all;
  for (const auto& s : strings) all += s;
  const std::string marker = "\n#line 0\n";
  const size_t at = all.find(marker);
  if (at == std::string::npos) return false;
  out.header = all.substr(0, at + 1);
  out.body = all.substr(at + marker.size());
  return true;
}

// Header defines that select nothing oovr draws: GLSL dialect macros, the
// enumerations' names, and constants the fast-light programs do not read.
bool ioq3_neutral(const std::string& d) {
  static const std::set<std::string> names = {"attribute",
                                              "varying",
                                              "texture2D",
                                              "textureCubeLod",
                                              "shadow2D",
                                              "gl_FragColor",
                                              "M_PI",
                                              "deformGen_t",
                                              "tcGen_t",
                                              "colorGen_t",
                                              "alphaGen_t",
                                              "r_FBufScale",
                                              "r_deluxeSpecular",
                                              "MAX_GLSL_BONES",
                                              "ROUGHNESS_MIPS",
                                              "GLOSS_IS_GLOSS",
                                              "GLOSS_IS_SMOOTHNESS",
                                              "GLOSS_IS_ROUGHNESS",
                                              "GLOSS_IS_SHININESS"};
  if (names.count(d)) return true;
  for (const char* prefix : {"DGEN_", "TCGEN_", "CGEN_", "AGEN_"})
    if (d.rfind(prefix, 0) == 0) return true;
  return false;
}

// The names a GLSL body declares at the start of a line as `uniform`,
// `varying` or `attribute` (`uniform vec4 u_Color;`, `uniform float
// u_DeformParams[5];`), whatever the spacing.
std::set<std::string> declarations(const std::string& body) {
  std::set<std::string> out;
  std::istringstream lines(body);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string qualifier, type, name;
    words >> qualifier >> type >> name;
    if (qualifier != "uniform" && qualifier != "varying" && qualifier != "attribute") continue;
    name = name.substr(0, name.find_first_of(";["));
    if (!name.empty()) out.insert(name);
  }
  return out;
}

}  // namespace

bool is_ioq3_program(const std::vector<std::vector<std::string>>& shader_sources) {
  if (shader_sources.empty()) return false;
  bool position = false;
  for (const auto& s : shader_sources) {
    Ioq3Source src;
    if (!split_ioq3(s, src)) return false;
    position = position || declarations(src.body).count("attr_Position") > 0;
  }
  return position;
}

ProgramRecipe ioq3_recipe(const std::vector<std::vector<std::string>>& shader_sources) {
  std::set<std::string> defines;
  std::map<std::string, float> constants;
  std::string bodies;
  for (const auto& s : shader_sources) {
    Ioq3Source src;
    if (!split_ioq3(s, src)) throw Error("a program mixing ioquake3's shaders with others");
    bodies += src.body;
    std::istringstream lines(src.header);
    std::string line;
    while (std::getline(lines, line)) {
      std::istringstream words(line);
      std::string directive, name, value;
      words >> directive >> name;
      if (directive != "#define" || name.empty()) continue;
      defines.insert(name);
      if (words >> value) {
        char* end = nullptr;
        const float v = std::strtof(value.c_str(), &end);
        if (end && *end == '\0') constants[name] = v;
      }
    }
  }
  ProgramRecipe r;
  r.ioq3 = true;
  Ioq3Stage& st = r.stage;
  // Which shader the body is, by what only it declares.
  const std::set<std::string> declared = declarations(bodies);
  const auto declares = [&](const char* name) { return declared.count(name) > 0; };
  std::string shader;
  if (declares("u_DlightInfo")) {
    st.shader = Ioq3Stage::Shader::dlight;
    shader = "dlight";
  } else if (declares("var_TexCoords")) {
    st.shader = Ioq3Stage::Shader::lightall;
    shader = "lightall";
  } else if (declares("var_DiffuseTex") && declares("u_BaseColor")) {
    st.shader = Ioq3Stage::Shader::generic;
    shader = "generic";
  } else {
    throw Error("ioquake3's programs other than its generic, lightall and dlight shaders (a post-process, fog or shadow pass)");
  }
  std::set<std::string> read;
  const auto use = [&](const char* d) {
    read.insert(d);
    return defines.count(d) > 0;
  };
  r.mode = "ioquake3 " + shader;
  r.position = "attr_Position";
  r.mvp = "u_ModelViewProjectionMatrix";
  r.uv = "attr_TexCoord0";
  // The second coordinates, which the stage reads for tcGen lightmap and
  // the lightmap's texel (ioq3_vertex's tex1).
  r.lightmap_uv = "attr_TexCoord1";
  r.colour = st.shader == Ioq3Stage::Shader::dlight ? "" : "attr_Color";
  r.layers.push_back({"u_DiffuseMap", TexCoords::surface, Combine::modulate, "", false});
  st.deform = use("USE_DEFORM_VERTEXES");
  if (st.shader != Ioq3Stage::Shader::dlight) {
    st.tcgen = use("USE_TCGEN");
    st.tcmod = use("USE_TCMOD");
    st.vertex_animation = use("USE_VERTEX_ANIMATION");
  }
  if (st.shader == Ioq3Stage::Shader::generic) {
    st.rgbagen = use("USE_RGBAGEN");
    st.fog = use("USE_FOG");
  }
  if (st.shader == Ioq3Stage::Shader::lightall) {
    // The fast light path (r_normalMapping 0, r_specularMapping 0):
    // gl_FragColor.rgb = diffuse.rgb x var_Color.rgb (x the lightmap's
    // texel); the per-pixel path's normal, deluxe, specular and cube maps
    // are refused below.
    const bool light = use("USE_LIGHT"), fast = use("USE_FAST_LIGHT");
    if (light && !fast) throw Error("ioquake3's lightall programs without USE_FAST_LIGHT (per-pixel lighting)");
    if (use("USE_LIGHTMAP")) {
      st.lightmap = true;
      r.layers.push_back({"u_LightMap", TexCoords::lightmap, Combine::modulate, "", false});
    }
    st.light_vector = use("USE_LIGHT_VECTOR");
    st.model_matrix = use("USE_MODELMATRIX");
    read.insert("USE_LIGHT_VERTEX");  // the vertex colour as the light: what var_Color is anyway
  }
  for (const auto& d : defines)
    if (!read.count(d) && !ioq3_neutral(d)) throw Error("ioquake3's " + shader + " programs with " + d);
  // The enumerations the stage compares with, from the header.
  Ioq3Stage::Constants& k = st.constants;
  const std::pair<const char*, float*> needed[] = {{"DGEN_WAVE_SIN", &k.wave_sin},
                                                   {"DGEN_WAVE_SQUARE", &k.wave_square},
                                                   {"DGEN_WAVE_TRIANGLE", &k.wave_triangle},
                                                   {"DGEN_WAVE_SAWTOOTH", &k.wave_sawtooth},
                                                   {"DGEN_WAVE_INVERSE_SAWTOOTH", &k.wave_inverse_sawtooth},
                                                   {"DGEN_BULGE", &k.bulge},
                                                   {"TCGEN_LIGHTMAP", &k.tcgen_lightmap},
                                                   {"TCGEN_ENVIRONMENT_MAPPED", &k.tcgen_environment},
                                                   {"TCGEN_VECTOR", &k.tcgen_vector},
                                                   {"CGEN_LIGHTING_DIFFUSE", &k.cgen_lighting_diffuse},
                                                   {"AGEN_LIGHTING_SPECULAR", &k.agen_lighting_specular},
                                                   {"AGEN_PORTAL", &k.agen_portal}};
  for (const auto& [name, value] : needed) {
    const auto it = constants.find(name);
    if (it == constants.end()) throw Error(std::string("ioquake3's ") + shader + " programs without the constant " + name);
    *value = it->second;
  }
  return r;
}

namespace {

float fract(float x) { return x - std::floor(x); }
float clamp01(float x) { return std::clamp(x, 0.0f, 1.0f); }

// What a division by zero or an overflow left in the colour (a light at the
// vertex, fog at its boundary) is taken as 0: GLSL leaves it undefined.
Ioq3VertexOut finite(Ioq3VertexOut out) {
  for (float& c : out.colour)
    if (!std::isfinite(c)) c = 0;
  for (float* f : {&out.uv.x, &out.uv.y, &out.position.x, &out.position.y, &out.position.z})
    if (!std::isfinite(*f)) *f = 0;
  return out;
}

}  // namespace

Ioq3VertexOut ioq3_vertex(const Ioq3Stage& st, const Ioq3Uniforms& u, const Ioq3VertexIn& in) {
  const Ioq3Stage::Constants& k = st.constants;
  Ioq3VertexOut out;
  Vec3 position = in.position, normal = in.normal;
  if (st.vertex_animation) {
    // mix(a, b, t) = a * (1 - t) + b * t
    position = in.position * (1 - u.vertex_lerp) + in.position2 * u.vertex_lerp;
    normal = in.normal * (1 - u.vertex_lerp) + in.normal2 * u.vertex_lerp;
  }
  if (st.deform) {
    // DeformPosition: along the normal by base + wave x amplitude (the
    // dlight shader leaves positions alone while u_DeformGen is 0).
    const float gen = u.deform_gen;
    if (!(st.shader == Ioq3Stage::Shader::dlight && gen == 0)) {
      const float base = u.deform_params[0], amplitude = u.deform_params[1], frequency = u.deform_params[3],
                  spread = u.deform_params[4];
      float phase = u.deform_params[2];
      if (gen == k.bulge) phase *= in.tex0.x;
      else phase += dot(position, Vec3{spread, spread, spread});
      const float value = phase + u.time * frequency;
      float func;
      if (gen == k.wave_sin) func = std::sin(value * 2 * kPi);
      else if (gen == k.wave_square)
        // generic: sign(fract(0.5 - value)); dlight: sign(0.5 - fract(value))
        func = st.shader == Ioq3Stage::Shader::dlight ? (0.5f - fract(value) > 0   ? 1.0f
                                                         : 0.5f - fract(value) < 0 ? -1.0f
                                                                                   : 0.0f)
                                                      : (fract(0.5f - value) > 0 ? 1.0f : 0.0f);
      else if (gen == k.wave_triangle) func = std::abs(fract(value + 0.75f) - 0.5f) * 4 - 1;
      else if (gen == k.wave_sawtooth) func = fract(value);
      else if (gen == k.wave_inverse_sawtooth) func = 1 - fract(value);
      else func = std::sin(value);
      position = position + normal * (base + func * amplitude);
    }
  }
  out.position = position;

  if (st.shader == Ioq3Stage::Shader::dlight) {
    // The light's disc projected along z: coordinates from the distance to
    // it, colour u_Color where the surface faces it, fading with height.
    const Vec3 dist = Vec3{u.dlight_info[0], u.dlight_info[1], u.dlight_info[2]} - position;
    out.uv = {dist.x * u.dlight_info[3] + 0.5f, dist.y * u.dlight_info[3] + 0.5f};
    float mod = dot(dist, normal) >= 0 ? 1.0f : 0.0f;  // step(0.0, x)
    mod *= clamp01(2 * (1 - std::abs(dist.z) * u.dlight_info[3]));
    for (int i = 0; i < 4; ++i) out.colour[size_t(i)] = u.colour[size_t(i)] * mod;
    return finite(out);
  }

  Vec2 tex = in.tex0;
  if (st.tcgen) {
    const float gen = u.tcgen;
    if (gen == k.tcgen_lightmap) {
      tex = in.tex1;
    } else if (gen == k.tcgen_environment) {
      const Vec3 viewer = normalize(u.local_view_origin - position);
      // reflect(I, N) = I - 2 dot(N, I) N
      const Vec3 ref = viewer - normal * (2 * dot(normal, viewer));
      tex = {ref.y * -0.5f + 0.5f, ref.z * 0.5f + 0.5f};
    } else if (gen == k.tcgen_vector) {
      tex = {dot(position, u.tcgen_vector0), dot(position, u.tcgen_vector1)};
    }
  }
  if (st.tcmod) {
    const float amplitude = u.off_turb[2], phase = u.off_turb[3] * 2 * kPi;
    const Vec2 st2{tex.x * u.tex_matrix[0] + (tex.y * u.tex_matrix[2] + u.off_turb[0]),
                   tex.x * u.tex_matrix[1] + (tex.y * u.tex_matrix[3] + u.off_turb[1])};
    const float ox = position.x + position.z, oy = position.y;
    tex = {st2.x + std::sin(ox * (2 * kPi / 1024) + phase) * amplitude,
           st2.y + std::sin(oy * (2 * kPi / 1024) + phase) * amplitude};
  }
  out.uv = tex;
  out.lightmap = in.tex1;

  for (int i = 0; i < 4; ++i) out.colour[size_t(i)] = u.vert_colour[size_t(i)] * in.colour[size_t(i)] + u.base_colour[size_t(i)];
  if (st.rgbagen) {
    // CalcColor
    if (u.colour_gen == k.cgen_lighting_diffuse) {
      const float incoming = clamp01(dot(normal, u.model_light_dir));
      out.colour[0] = clamp01(u.directed_light.x * incoming + u.ambient_light.x);
      out.colour[1] = clamp01(u.directed_light.y * incoming + u.ambient_light.y);
      out.colour[2] = clamp01(u.directed_light.z * incoming + u.ambient_light.z);
    }
    const Vec3 viewer = u.local_view_origin - position;
    if (u.alpha_gen == k.agen_lighting_specular) {
      const Vec3 light_dir = normalize(Vec3{-960, 1980, 96} - position);
      const Vec3 reflected = (light_dir - normal * (2 * dot(normal, light_dir))) * -1.0f;
      float a = clamp01(dot(reflected, normalize(viewer)));
      a *= a;
      a *= a;
      out.colour[3] = a;
    } else if (u.alpha_gen == k.agen_portal) {
      out.colour[3] = clamp01(length(viewer) / u.portal_range);
    }
  }
  if (st.fog) {
    // CalcFog: the depth into the fog volume times the distance, its root
    // attenuating the colour's channels that u_FogColorMask selects.
    const Vec4 p4{position.x, position.y, position.z, 1};
    const auto dot4 = [&](const std::array<float, 4>& v) { return p4.x * v[0] + p4.y * v[1] + p4.z * v[2] + p4.w * v[3]; };
    const float s = dot4(u.fog_distance) * 8;
    float t = dot4(u.fog_depth);
    const float eye_outside = u.fog_eye_t < 0 ? 1.0f : 0.0f;
    const float fogged = t >= eye_outside ? 1.0f : 0.0f;
    t += 1e-6f;
    t *= fogged / (t - u.fog_eye_t * eye_outside);
    const float fog = std::sqrt(clamp01(s * t));
    for (int i = 0; i < 4; ++i) out.colour[size_t(i)] *= 1 - u.fog_colour_mask[size_t(i)] * fog;
  }
  if (st.light_vector) {
    // The fast light: var_Color.rgb *= directed x (attenuation x N.L) +
    // ambient, from the light's position in world space.
    Vec3 pos = position, nrm = normal;
    if (st.model_matrix) {
      const Vec4 q = transform_point(u.model_matrix, pos);
      pos = {q.x, q.y, q.z};
      const Mat4& m = u.model_matrix;
      nrm = {m.at(0, 0) * normal.x + m.at(0, 1) * normal.y + m.at(0, 2) * normal.z,
             m.at(1, 0) * normal.x + m.at(1, 1) * normal.y + m.at(1, 2) * normal.z,
             m.at(2, 0) * normal.x + m.at(2, 1) * normal.y + m.at(2, 2) * normal.z};
    }
    const Vec3 l = Vec3{u.light_origin[0], u.light_origin[1], u.light_origin[2]} - pos * u.light_origin[3];
    const float sqr = dot(l, l);
    const float nl = clamp01(dot(normalize(nrm), l) / std::sqrt(sqr));
    // CalcLightAttenuation(point, normDist)
    const float norm_dist = u.light_radius * u.light_radius / sqr;
    const float attenuation = clamp01((0.5f * norm_dist - 1.5f) * u.light_origin[3] + 1);
    const Vec3 light = u.directed_light * (attenuation * nl) + u.ambient_light;
    out.colour[0] *= light.x;
    out.colour[1] *= light.y;
    out.colour[2] *= light.z;
  }
  return finite(out);
}

}  // namespace oovr
