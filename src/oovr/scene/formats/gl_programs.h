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
// The convention modelled is DarkPlaces' (Nexuiz) OpenGL 3.2 renderer, its
// one shader (shader_glsl.h) compiled per permutation.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "oovr/scene/material.h"

namespace oovr {

// The `#define NAME` lines of a shader's source strings other than its last
// (DarkPlaces passes the version, then one string per permutation define,
// then the shader body, whose own #defines are not permutations).
std::set<std::string> permutation_defines(const std::vector<std::string>& source_strings);

struct ProgramRecipe {
  std::string mode;  // the permutation's MODE_ define
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

}  // namespace oovr
