// What a draw through a GLSL program computes, in oovr's terms
// (docs/real-frames.md, "GLSL games"). oovr does not run shaders: a
// program is recognised by its engine's conventions (the names it binds its
// attributes and uniforms to, and the permutation #defines it compiles
// with), and each permutation it draws with is mapped onto a pass of
// oovr's scene model: which attribute holds the positions and which uniform
// the matrix that projects them, which samplers it fetches from with which
// coordinates and how it combines them. A permutation whose colour oovr's
// passes cannot compute (a screen-space effect, a render-to-texture pass)
// is refused with its name; where the colour is approximated the recipe
// says how, and the import counts those draws in a scene note.
//
// Two conventions are modelled: DarkPlaces' (Nexuiz) OpenGL 3.2 renderer,
// its one shader (shader_glsl.h) compiled per permutation, and ioquake3's
// `opengl2` renderer (renderergl2, OpenArena's default), its generic,
// lightall and dlight shaders, whose vertex stage oovr evaluates per vertex
// (ioq3_vertex) and whose fragment stage is a product of textures.
#pragma once

#include <array>
#include <set>
#include <string>
#include <vector>

#include "oovr/core/math.h"
#include "oovr/scene/material.h"

namespace oovr {

// The `#define NAME` lines of a shader's source strings other than its last
// (DarkPlaces passes the version, then one string per permutation define,
// then the shader body, whose own #defines are not permutations).
std::set<std::string> permutation_defines(const std::vector<std::string>& source_strings);

// What ioquake3's opengl2 vertex shaders compute (glsl/generic_vp.glsl,
// lightall_vp.glsl, dlight_vp.glsl), as its permutation defines select.
struct Ioq3Stage {
  enum class Shader : uint8_t { generic, lightall, dlight } shader = Shader::generic;
  bool deform = false;            // USE_DEFORM_VERTEXES: positions moved along the normal by a wave
  bool tcgen = false;             // USE_TCGEN: coordinates from the lightmap's, an environment map or vectors
  bool tcmod = false;             // USE_TCMOD: an affine map and a turbulence of the coordinates
  bool rgbagen = false;           // USE_RGBAGEN: colour from a light direction, alpha from specular or portal range
  bool fog = false;               // USE_FOG: the colour attenuated by fog
  bool vertex_animation = false;  // USE_VERTEX_ANIMATION: two key frames mixed by u_VertexLerp
  bool lightmap = false;          // USE_LIGHTMAP: the lightmap (u_LightMap) multiplies the colour
  bool light_vector = false;      // USE_LIGHT_VECTOR with USE_FAST_LIGHT: a light's diffuse term per vertex
  bool model_matrix = false;      // USE_MODELMATRIX: the light vector's position in world space
  // The header's constants the stage compares its uniforms with (#define
  // DGEN_WAVE_SIN 1, ...: ioquake3's values by default; a program's own
  // header sets them).
  struct Constants {
    float wave_sin = 1, wave_square = 2, wave_triangle = 3, wave_sawtooth = 4, wave_inverse_sawtooth = 5, bulge = 7;
    float tcgen_lightmap = 2, tcgen_environment = 4, tcgen_vector = 6;
    float cgen_lighting_diffuse = 11, agen_lighting_specular = 6, agen_portal = 8;
  } constants;
};

// A draw's uniforms that ioquake3's vertex stages read (0 where unset).
struct Ioq3Uniforms {
  std::array<float, 4> base_colour{}, vert_colour{}, tex_matrix{1, 0, 0, 1}, off_turb{};
  float tcgen = 0;
  Vec3 tcgen_vector0, tcgen_vector1, local_view_origin;
  float colour_gen = 0, alpha_gen = 0, portal_range = 0;
  Vec3 ambient_light, directed_light, model_light_dir;
  float deform_gen = 0, time = 0;
  std::array<float, 5> deform_params{};
  std::array<float, 4> fog_distance{}, fog_depth{}, fog_colour_mask{};
  float fog_eye_t = 0;
  float vertex_lerp = 0;
  Mat4 model_matrix;
  std::array<float, 4> light_origin{};
  float light_radius = 0;
  std::array<float, 4> dlight_info{}, colour{};  // the dlight shader's
};

struct Ioq3VertexIn {
  Vec3 position, normal, position2, normal2;
  std::array<float, 4> colour{1, 1, 1, 1};
  Vec2 tex0, tex1;
};

struct Ioq3VertexOut {
  Vec3 position;                  // the object-space position gl_Position projects
  Vec2 uv, lightmap;              // var_DiffuseTex (var_TexCoords.xy, var_Tex1) and var_TexCoords.zw
  std::array<float, 4> colour{};  // var_Color, unclamped
};

// One vertex through the stage's vertex shader, as its GLSL computes it.
Ioq3VertexOut ioq3_vertex(const Ioq3Stage& stage, const Ioq3Uniforms& u, const Ioq3VertexIn& in);

struct ProgramRecipe {
  std::string mode;  // the permutation's MODE_ define (DarkPlaces), or ioquake3's shader and defines
  // ioquake3's opengl2 programs: the vertex stage oovr evaluates per vertex.
  bool ioq3 = false;
  Ioq3Stage stage;
  // Attributes (by the name the program binds them to): positions, the
  // surface's and the lightmap's (or second texture's) coordinates, the
  // vertex colour; "" when the permutation does not read one.
  std::string position, uv, lightmap_uv, colour;
  std::string mvp;         // the uniform that projects positions to clip space
  std::string tex_matrix;  // the uniform that transforms `uv` ("" none)
  struct Layer {
    std::string sampler;  // the sampler uniform
    TexCoords coords = TexCoords::surface;
    Combine combine = Combine::modulate;
    // An added layer's tint (a vec3 uniform): its mean is the layer's
    // scale, times the light where the program adds it before lighting.
    std::string tint;
    bool lit = false;
  };
  std::vector<Layer> layers;  // in oovr's order (scene/material.h)
  // The pass colour: RGB from this vec3 uniform ("" white), alpha from
  // `alpha` ("" 1); the vertex colour multiplies it where `colour` is set.
  std::string colour_rgb, alpha;
  bool alpha_kill = false;  // discards texels of alpha under 0.5 (an alpha test)
  bool depth_only = false;  // writes no colour
  // A copy of the view (rendered into a texture, the first layer's) into
  // the window, which changes nothing while each of these uniforms'
  // components holds its value (a view tint of alpha 0, saturation 1).
  bool composite = false;
  struct Identity {
    std::string uniform;
    int component;
    float value;
  };
  std::vector<Identity> identity_when;
  std::string gamma_ramps;    // a sampler whose texture must be the identity ramp ("" none)
  std::string approximation;  // how the colour differs from the program's, "" when it does not
  // The program adds the diffuse texture times this vec3 uniform (an
  // ambient light) to the light: oovr draws it as a third layer adding the
  // diffuse texture again, scaled by its mean ("" none).
  std::string ambient;
  // Lit by a light direction (models): the colour is ambient + diffuse x
  // max(0, N.L), evaluated per vertex from the vertex normal (attribute
  // `normal`) and the uniform `light_dir`, in model space ("" none).
  std::string light_dir, normal, light_ambient, light_diffuse;
};

// DarkPlaces' 2-D texture samplers: those of them a program keeps (the
// compiler drops what a permutation does not read) are what it fetches;
// the ones a recipe does not combine are drawn as fetch layers.
// Each with the kind of layer its texture is (normal and gloss maps cost
// what a program computes with them: pipeline/shader_cost.h).
struct SamplerKind {
  const char* name;
  LayerKind kind;
};
const std::vector<SamplerKind>& darkplaces_2d_samplers();

// The recipe of a DarkPlaces permutation; throws Error naming the programs
// oovr does not draw ("DarkPlaces' MODE_WATER programs").
ProgramRecipe darkplaces_recipe(const std::set<std::string>& defines);

// Whether a program's shader sources are ioquake3's opengl2 renderer's: one
// string each, a header of #defines closed by `#line 0`, then a body whose
// attributes are named attr_*.
bool is_ioq3_program(const std::vector<std::vector<std::string>>& shader_sources);

// The recipe of an ioquake3 opengl2 program from its shaders' sources;
// throws Error naming what oovr does not draw ("ioquake3's lightall
// programs with USE_NORMALMAP").
ProgramRecipe ioq3_recipe(const std::vector<std::vector<std::string>>& shader_sources);

}  // namespace oovr
