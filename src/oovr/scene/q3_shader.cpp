#include "oovr/scene/q3_shader.h"

#include <cstdlib>

#include "oovr/scene/pk3.h"

namespace oovr {
namespace {

struct Token {
  std::string text;
  int line;
};

// Splits a script into tokens: braces are tokens of their own, quotes group,
// // and /* */ comments are skipped.
std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  int line = 1;
  size_t i = 0;
  while (i < s.size()) {
    const char c = s[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '/' && i + 1 < s.size() && s[i + 1] == '/') {
      while (i < s.size() && s[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < s.size() && s[i + 1] == '*') {
      i += 2;
      while (i + 1 < s.size() && !(s[i] == '*' && s[i + 1] == '/')) line += s[i++] == '\n';
      i += 2;
    } else if (c == '{' || c == '}') {
      out.push_back({std::string(1, c), line});
      ++i;
    } else if (c == '"') {
      size_t j = i + 1;
      while (j < s.size() && s[j] != '"' && s[j] != '\n') ++j;
      out.push_back({s.substr(i + 1, j - i - 1), line});
      i = j + 1;
    } else {
      size_t j = i;
      while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j])) && s[j] != '{' && s[j] != '}' &&
             !(s[j] == '/' && j + 1 < s.size() && (s[j + 1] == '/' || s[j + 1] == '*')))
        ++j;
      out.push_back({s.substr(i, j - i), line});
      i = j;
    }
  }
  return out;
}

std::string lower(std::string s) { return normalize_game_path(std::move(s)); }

struct Stage {
  std::string image;
  bool clamp = false, blended = false, alpha_test = false;
  float cutoff = 0.5f, scale_s = 1, scale_t = 1;
  bool lightmap_or_white = false;
};

}  // namespace

void parse_q3_shader_script(const std::string& text, const std::string& file, Q3ShaderSet& set) {
  const std::vector<Token> t = tokenize(text);
  size_t i = 0;
  auto note = [&](const std::string& what, int line) {
    set.notes.push_back(file + ":" + std::to_string(line) + ": " + what);
  };
  // The tokens after position k that stand on the same line as token k.
  auto args = [&](size_t k) {
    std::vector<std::string> a;
    for (size_t j = k + 1; j < t.size() && t[j].line == t[k].line && t[j].text != "{" && t[j].text != "}"; ++j)
      a.push_back(t[j].text);
    return a;
  };
  while (i < t.size()) {
    const Token name = t[i++];
    if (name.text == "{" || name.text == "}") {
      note("unexpected '" + name.text + "' where a shader name belongs", name.line);
      continue;
    }
    if (i >= t.size() || t[i].text != "{") {
      note("shader '" + name.text + "' has no body", name.line);
      continue;
    }
    ++i;
    Q3Shader sh;
    sh.name = lower(name.text);
    std::string editor_image, sky_box;
    std::vector<Stage> stages;
    int depth = 1;
    Stage stage;
    while (i < t.size() && depth > 0) {
      const Token& tok = t[i];
      if (tok.text == "{") {
        ++depth;
        if (depth == 2) stage = Stage{};
        ++i;
        continue;
      }
      if (tok.text == "}") {
        if (depth == 2) stages.push_back(stage);
        --depth;
        ++i;
        continue;
      }
      const std::string key = lower(tok.text);
      const std::vector<std::string> a = args(i);
      i += 1 + a.size();
      if (depth == 1) {
        if (key == "cull" && !a.empty()) {
          const std::string v = lower(a[0]);
          sh.two_sided = v == "none" || v == "disable" || v == "twosided";
        } else if (key == "surfaceparm" && !a.empty()) {
          const std::string v = lower(a[0]);
          if (v == "nodraw") sh.nodraw = true;
          if (v == "sky") sh.sky = true;
        } else if (key == "fogparms") {
          sh.fog = true;
        } else if (key == "qer_editorimage" && !a.empty()) {
          editor_image = a[0];
        } else if (key == "skyparms" && !a.empty() && a[0] != "-") {
          sky_box = a[0] + "_ft";
        }
      } else if (depth == 2) {
        if ((key == "map" || key == "clampmap") && !a.empty()) {
          const std::string v = lower(a[0]);
          if (v == "$lightmap" || v == "$whiteimage" || v == "*white") stage.lightmap_or_white = true;
          else stage.image = a[0];
          stage.clamp = key == "clampmap";
        } else if (key == "animmap" && a.size() >= 2) {
          stage.image = a[1];  // frame 0
        } else if (key == "blendfunc") {
          // GL_ONE GL_ZERO is opaque; everything else blends with the frame.
          const std::string v = a.empty() ? "" : lower(a[0]);
          const std::string w = a.size() > 1 ? lower(a[1]) : "";
          stage.blended = !(v == "gl_one" && w == "gl_zero");
        } else if (key == "alphafunc" && !a.empty()) {
          const std::string v = lower(a[0]);
          stage.alpha_test = true;
          stage.cutoff = v == "gt0" ? 1.0f / 255.0f : 0.5f;  // GE128 and LT128 test at one half
        } else if (key == "tcmod" && a.size() >= 3 && lower(a[0]) == "scale") {
          stage.scale_s = std::strtof(a[1].c_str(), nullptr);
          stage.scale_t = std::strtof(a[2].c_str(), nullptr);
          if (!(stage.scale_s != 0 && stage.scale_t != 0)) stage.scale_s = stage.scale_t = 1;
        }
      } else {
        note("shader '" + sh.name + "' nests braces deeper than a stage", tok.line);
      }
    }
    if (depth > 0) {
      note("shader '" + sh.name + "' is not closed before the end of the file", name.line);
      break;
    }
    const Stage* chosen = nullptr;
    for (const Stage& s : stages)
      if (!s.image.empty()) {
        chosen = &s;
        break;
      }
    if (chosen) {
      sh.image = chosen->image;
      sh.clamp = chosen->clamp;
      // A blending stage drawn after another (e.g. over the $lightmap
      // stage) only combines the two; the surface is translucent when its
      // first stage already blends with the frame.
      sh.blended = chosen->blended && chosen == &stages.front();
      sh.alpha_test = chosen->alpha_test;
      sh.alpha_cutoff = chosen->cutoff;
      sh.tc_scale_s = chosen->scale_s;
      sh.tc_scale_t = chosen->scale_t;
    } else if (!sky_box.empty() && sh.sky) {
      sh.image = sky_box;
    } else {
      sh.image = editor_image;
    }
    set.shaders[sh.name] = sh;
  }
}

}  // namespace oovr
