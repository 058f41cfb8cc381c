// Quake 3 shader scripts (scripts/*.shader): the part of them that decides
// which image a surface shows and how it is drawn. oovr draws one texture per
// surface (plus the lightmap), so a multi-stage shader is reduced to its first
// stage that samples an image.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace oovr {

struct Q3Shader {
  std::string name;         // lower case
  std::string image;        // image path of the chosen stage (may lack or have a wrong extension)
  bool clamp = false;       // clampmap
  bool two_sided = false;   // cull none / disable / twosided
  bool nodraw = false;      // surfaceparm nodraw
  bool sky = false;         // surfaceparm sky
  bool fog = false;         // fogparms: a fog volume, not an opaque surface
  bool blended = false;     // translucent: the first stage blends with the frame (drawn opaque by oovr)
  bool alpha_test = false;  // alphaFunc on the chosen stage
  float alpha_cutoff = 0.5f;
  float tc_scale_s = 1.0f, tc_scale_t = 1.0f;  // static tcMod scale of the chosen stage
};

struct Q3ShaderSet {
  std::map<std::string, Q3Shader> shaders;  // by lower-case name
  std::vector<std::string> notes;           // problems found while parsing (the engine tolerates them too)
};

// Parses one shader script and adds its shaders to `set`; a shader defined
// again replaces the earlier definition. Parsing never throws: a malformed
// script adds a note naming the file and line and keeps what was read.
void parse_q3_shader_script(const std::string& text, const std::string& file, Q3ShaderSet& set);

}  // namespace oovr
