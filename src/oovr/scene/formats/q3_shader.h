// Quake 3 shader scripts (scripts/*.shader): every stage of every shader,
// as ioquake3's renderer parses it (code/renderergl1/tr_shader.c), and the
// passes ioquake3 draws a surface with (q3_passes).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "oovr/scene/material.h"

namespace oovr {

struct Q3Stage {
  enum class Source { image, lightmap, white };
  Source source = Source::image;
  std::string image;  // map / clampMap / frame 0 of animMap (may lack or have a wrong extension)
  bool clamp = false;
  bool detail = false;  // "detail": drawn only with r_detailTextures (on by default)
  // blendFunc; GL_ONE GL_ZERO (or none) is opaque.
  BlendFactor src = BlendFactor::one, dst = BlendFactor::zero;
  AlphaFunc alpha_func = AlphaFunc::always;
  float alpha_ref = 0.5f;
  // Blended stages write depth only when the stage says depthWrite.
  bool depth_write = true;
  bool depth_equal = false;  // depthFunc equal
  // rgbGen / alphaGen, as written ("identity" when absent); a constant
  // colour when rgbGen const / alphaGen const.
  std::string rgb_gen = "identity", alpha_gen = "identity";
  Vec4 colour{1, 1, 1, 1};
  bool tc_lightmap = false;              // tcGen lightmap (or the $lightmap stage)
  std::vector<TexMod> mods;              // tcMod scale and scroll, in order
  std::vector<std::string> unsupported;  // other tcMod / tcGen kinds seen (drawn without them)

  bool blended() const { return !(src == BlendFactor::one && dst == BlendFactor::zero); }
};

struct Q3Shader {
  std::string name;  // lower case
  std::vector<Q3Stage> stages;
  bool two_sided = false;    // cull none / disable / twosided
  bool nodraw = false;       // surfaceparm nodraw
  bool sky = false;          // surfaceparm sky
  bool fog = false;          // fogparms: a fog volume, not an opaque surface
  float sort = 0;            // explicit sort key; 0 = decided from the stages
  std::string sky_box;       // skyParms far box base name ("" or "-" for none)
  std::string editor_image;  // qer_editorImage
};

struct Q3ShaderSet {
  std::map<std::string, Q3Shader> shaders;  // by lower-case name
  std::vector<std::string> notes;           // problems found while parsing (the engine tolerates them too)
};

// Parses one shader script and adds its shaders to `set`; a shader defined
// again replaces the earlier definition. Parsing never throws: a malformed
// script adds a note naming the file and line and keeps what was read.
void parse_q3_shader_script(const std::string& text, const std::string& file, Q3ShaderSet& set);

// Quake 3's sort keys (tr_local.h's shaderSort_t).
namespace q3_sort {
constexpr float portal = 1, environment = 2, opaque = 3, decal = 4, see_through = 5, banner = 6, underwater = 8, blend0 = 9,
                nearest = 16;
}

// A stage turned into a pass layer needs its texture; the loader supplies
// it (an index into Scene::textures, or -1 when the stage has no image).
struct Q3TextureLookup {
  virtual ~Q3TextureLookup() = default;
  virtual int image(const Q3Stage& stage) = 0;  // the stage's image (or a placeholder)
  virtual int lightmap() = 0;                   // the surface's lightmap, or -1 (vertex lit)
};

struct Q3Passes {
  std::vector<Pass> passes;
  float sort = q3_sort::opaque;
  int collapsed = 0;  // 1 when stages 0 and 1 became one multitexture pass
};

// The passes ioquake3 draws a surface with: every stage in shader order;
// stages 0 and 1 collapsed into one multitexture pass where
// CollapseMultitexture allows it; GL_LEQUAL (GL_EQUAL with depthFunc equal)
// for every pass; the sort key FinishShader decides. A shader without a
// script is ioquake3's implicit one: the lightmap times the image, or the
// image alone for a surface without lightmap.
Q3Passes q3_passes(const Q3Shader* shader, Q3TextureLookup& textures);

}  // namespace oovr
