#include "oovr/scene/formats/q3_shader.h"

#include <cmath>
#include <cstdlib>

#include "oovr/scene/formats/pk3.h"

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

// A number, or `fallback` when the text is not one (the engine's atof gives 0).
float number(const std::vector<std::string>& a, size_t i, float fallback) {
  if (i >= a.size()) return fallback;
  char* end = nullptr;
  const float v = std::strtof(a[i].c_str(), &end);
  return end != a[i].c_str() && std::isfinite(v) ? v : fallback;
}

bool blend_factor(const std::string& name, BlendFactor& f) {
  static const std::pair<const char*, BlendFactor> names[] = {{"gl_zero", BlendFactor::zero},
                                                              {"gl_one", BlendFactor::one},
                                                              {"gl_src_color", BlendFactor::src_colour},
                                                              {"gl_one_minus_src_color", BlendFactor::one_minus_src_colour},
                                                              {"gl_src_alpha", BlendFactor::src_alpha},
                                                              {"gl_one_minus_src_alpha", BlendFactor::one_minus_src_alpha},
                                                              {"gl_dst_color", BlendFactor::dst_colour},
                                                              {"gl_one_minus_dst_color", BlendFactor::one_minus_dst_colour},
                                                              {"gl_dst_alpha", BlendFactor::dst_alpha},
                                                              {"gl_one_minus_dst_alpha", BlendFactor::one_minus_dst_alpha}};
  for (const auto& [n, v] : names)
    if (name == n) {
      f = v;
      return true;
    }
  return false;
}

// One stage's keyword (tr_shader.c's ParseStage). Keywords that change
// nothing oovr models (e.g. nopicmip) are skipped, as the engine skips
// unknown ones.
void parse_stage_key(const std::string& key, const std::vector<std::string>& a, Q3Stage& st, bool& depth_write_explicit,
                     std::string& problem) {
  if ((key == "map" || key == "clampmap") && !a.empty()) {
    const std::string v = lower(a[0]);
    if (v == "$lightmap") {
      st.source = Q3Stage::Source::lightmap;
      st.tc_lightmap = true;
    } else if (v == "$whiteimage" || v == "*white") {
      st.source = Q3Stage::Source::white;
    } else {
      st.source = Q3Stage::Source::image;
      st.image = a[0];
    }
    st.clamp = key == "clampmap";
  } else if (key == "animmap" && a.size() >= 2) {
    st.source = Q3Stage::Source::image;
    st.image = a[1];  // frame 0
  } else if (key == "blendfunc" && !a.empty()) {
    const std::string v = lower(a[0]);
    if (v == "add") {
      st.src = st.dst = BlendFactor::one;
    } else if (v == "filter") {
      st.src = BlendFactor::dst_colour;
      st.dst = BlendFactor::zero;
    } else if (v == "blend") {
      st.src = BlendFactor::src_alpha;
      st.dst = BlendFactor::one_minus_src_alpha;
    } else if (a.size() < 2 || !blend_factor(v, st.src) || !blend_factor(lower(a[1]), st.dst)) {
      problem = "bad blendFunc";
      return;
    }
    // Blended stages stop writing depth unless they say depthWrite.
    if (!depth_write_explicit) st.depth_write = !st.blended();
  } else if (key == "alphafunc" && !a.empty()) {
    const std::string v = lower(a[0]);
    if (v == "gt0") {
      st.alpha_func = AlphaFunc::greater;
      st.alpha_ref = 0.0f;
    } else if (v == "lt128") {
      st.alpha_func = AlphaFunc::less;
      st.alpha_ref = 0.5f;
    } else if (v == "ge128") {
      st.alpha_func = AlphaFunc::gequal;
      st.alpha_ref = 0.5f;
    } else {
      problem = "unknown alphaFunc '" + a[0] + "'";
    }
  } else if (key == "depthwrite") {
    st.depth_write = true;
    depth_write_explicit = true;
  } else if (key == "depthfunc" && !a.empty()) {
    st.depth_equal = lower(a[0]) == "equal";
  } else if (key == "detail") {
    st.detail = true;
  } else if (key == "rgbgen" && !a.empty()) {
    st.rgb_gen = lower(a[0]);
    if (st.rgb_gen == "const") {
      // rgbGen const ( r g b ): the parentheses are tokens of their own.
      std::vector<float> v;
      for (size_t i = 1; i < a.size(); ++i)
        if (a[i] != "(" && a[i] != ")") v.push_back(number(a, i, 0.0f));
      if (v.size() >= 3) st.colour = {v[0], v[1], v[2], st.colour.w};
    }
  } else if (key == "alphagen" && !a.empty()) {
    st.alpha_gen = lower(a[0]);
    if (st.alpha_gen == "const") st.colour.w = number(a, 1, 1.0f);
  } else if (key == "tcgen" || key == "texgen") {
    const std::string v = a.empty() ? "" : lower(a[0]);
    if (v == "lightmap") st.tc_lightmap = true;
    else if (v != "base" && v != "texture") st.unsupported.push_back("tcGen " + v);
  } else if (key == "tcmod" && !a.empty()) {
    const std::string v = lower(a[0]);
    if (v == "scale" && a.size() >= 3) {
      st.mods.push_back({TexMod::Kind::scale, number(a, 1, 1.0f), number(a, 2, 1.0f)});
    } else if (v == "scroll" && a.size() >= 3) {
      st.mods.push_back({TexMod::Kind::scroll, number(a, 1, 0.0f), number(a, 2, 0.0f)});
    } else {
      st.unsupported.push_back("tcMod " + v);
    }
  }
}

}  // namespace

void parse_q3_shader_script(const std::string& text, const std::string& file, Q3ShaderSet& set) {
  const std::vector<Token> t = tokenize(text);
  size_t i = 0;
  auto note = [&](const std::string& what, int line) { set.notes.push_back(file + ":" + std::to_string(line) + ": " + what); };
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
    int depth = 1;
    Q3Stage stage;
    bool depth_write_explicit = false;
    while (i < t.size() && depth > 0) {
      const Token& tok = t[i];
      if (tok.text == "{") {
        ++depth;
        if (depth == 2) {
          stage = Q3Stage{};
          depth_write_explicit = false;
        }
        ++i;
        continue;
      }
      if (tok.text == "}") {
        if (depth == 2) sh.stages.push_back(stage);
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
          sh.editor_image = a[0];
        } else if (key == "skyparms" && !a.empty()) {
          sh.sky_box = a[0] == "-" ? "" : a[0];
        } else if (key == "sort" && !a.empty()) {
          const std::string v = lower(a[0]);
          const std::pair<const char*, float> sorts[] = {{"portal", q3_sort::portal},
                                                         {"sky", q3_sort::environment},
                                                         {"opaque", q3_sort::opaque},
                                                         {"decal", q3_sort::decal},
                                                         {"seethrough", q3_sort::see_through},
                                                         {"banner", q3_sort::banner},
                                                         {"additive", 10},
                                                         {"nearest", q3_sort::nearest},
                                                         {"underwater", q3_sort::underwater}};
          sh.sort = number(a, 0, 0.0f);
          for (const auto& [n, s] : sorts)
            if (v == n) sh.sort = s;
        } else if (key == "polygonoffset") {
          if (sh.sort == 0) sh.sort = q3_sort::decal;
        }
      } else if (depth == 2) {
        std::string problem;
        parse_stage_key(key, a, stage, depth_write_explicit, problem);
        if (!problem.empty()) note("shader '" + sh.name + "': " + problem, tok.line);
      } else {
        note("shader '" + sh.name + "' nests braces deeper than a stage", tok.line);
      }
    }
    if (depth > 0) {
      note("shader '" + sh.name + "' is not closed before the end of the file", name.line);
      break;
    }
    if (sh.stages.size() > 8) {  // MAX_SHADER_STAGES
      note("shader '" + sh.name + "' has " + std::to_string(sh.stages.size()) + " stages; the engine draws the first 8",
           name.line);
      sh.stages.resize(8);
    }
    set.shaders[sh.name] = sh;
  }
}

namespace {

bool same(BlendFactor a1, BlendFactor a2, BlendFactor b1, BlendFactor b2) { return a1 == b1 && a2 == b2; }

// tr_shader.c's collapse table: (stage 0's blend, stage 1's blend) ->
// (texture environment, the pass's blend). "Opaque" is GL_ONE GL_ZERO.
bool collapse_rule(const Q3Stage& a, const Q3Stage& b, Combine& combine, BlendFactor& src, BlendFactor& dst) {
  using F = BlendFactor;
  const bool a_opaque = !a.blended();
  const bool a_filter = same(a.src, a.dst, F::dst_colour, F::zero) || same(a.src, a.dst, F::zero, F::src_colour);
  const bool b_filter = same(b.src, b.dst, F::dst_colour, F::zero) || same(b.src, b.dst, F::zero, F::src_colour);
  const bool a_add = same(a.src, a.dst, F::one, F::one), b_add = same(b.src, b.dst, F::one, F::one);
  if (b_filter && (a_opaque || a_filter)) {
    combine = Combine::modulate;
    src = a_opaque ? F::one : F::dst_colour;
    dst = F::zero;
    return true;
  }
  if (b_add && (a_opaque || a_add)) {
    combine = Combine::add;
    src = F::one;
    dst = a_opaque ? F::zero : F::one;
    return true;
  }
  return false;
}

bool can_collapse(const Q3Stage& a, const Q3Stage& b, Combine& combine, BlendFactor& src, BlendFactor& dst) {
  // Identical state other than blending and depth writes.
  if (a.alpha_func != b.alpha_func || a.alpha_ref != b.alpha_ref || a.depth_equal != b.depth_equal) return false;
  if (!collapse_rule(a, b, combine, src, dst)) return false;
  if (a.rgb_gen != b.rgb_gen || a.alpha_gen != b.alpha_gen) return false;
  if (combine == Combine::add && a.rgb_gen != "identity") return false;  // an add collapse needs identity colours
  // Waveforms must match exactly; oovr keeps no wave parameters, so two
  // wave generators are not merged.
  if (a.rgb_gen == "wave" || a.alpha_gen == "wave") return false;
  return true;
}

// A stage's layer: what it samples (none for a white stage).
std::vector<TextureLayer> stage_layers(const Q3Stage& st, Q3TextureLookup& textures) {
  TextureLayer l;
  l.mods = st.mods;
  if (st.source == Q3Stage::Source::lightmap) {
    l.kind = LayerKind::lightmap;
    l.texture = textures.lightmap();
    l.coords = TexCoords::lightmap;
  } else if (st.source == Q3Stage::Source::image) {
    l.kind = st.detail ? LayerKind::detail : LayerKind::diffuse;
    l.texture = textures.image(st);
    l.coords = st.tc_lightmap ? TexCoords::lightmap : TexCoords::surface;
  }
  if (l.texture < 0) return {};  // a white stage, or $lightmap on a vertex-lit surface (the engine's white image)
  return {l};
}

Pass stage_pass(const Q3Stage& st, std::vector<TextureLayer> layers) {
  Pass p;
  p.layers = std::move(layers);
  p.colour = st.colour;
  p.src = st.src;
  p.dst = st.dst;
  p.alpha_func = st.alpha_func;
  p.alpha_ref = st.alpha_ref;
  p.depth_func = st.depth_equal ? DepthFunc::equal : DepthFunc::lequal;  // Quake 3 draws with GL_LEQUAL
  p.depth_write = st.depth_write;
  return p;
}

}  // namespace

Q3Passes q3_passes(const Q3Shader* shader, Q3TextureLookup& textures) {
  std::vector<Q3Stage> stages;
  if (shader) {
    stages = shader->stages;
  } else {
    // ioquake3's implicit shader: the lightmap, then the image filtered by it.
    if (textures.lightmap() >= 0) {
      Q3Stage lm;
      lm.source = Q3Stage::Source::lightmap;
      lm.tc_lightmap = true;
      stages.push_back(lm);
      Q3Stage img;
      img.src = BlendFactor::dst_colour;
      img.dst = BlendFactor::zero;
      img.depth_write = false;
      stages.push_back(img);
    } else {
      stages.push_back(Q3Stage{});
    }
  }
  Q3Passes out;
  // The sort key FinishShader decides: sky, else explicit, else from the
  // first stage's blending (a blended first stage with depth writes is a
  // see-through grate, without them a blend), else opaque.
  if (shader && shader->sky) out.sort = q3_sort::environment;
  else if (shader && shader->sort > 0) out.sort = shader->sort;
  else if (!stages.empty() && stages.front().blended())
    out.sort = stages.front().depth_write ? q3_sort::see_through : q3_sort::blend0;
  size_t first = 0;
  Combine combine;
  BlendFactor src, dst;
  if (stages.size() >= 2 && can_collapse(stages[0], stages[1], combine, src, dst)) {
    // One multitexture pass: the image in unit 0, the lightmap in unit 1
    // (tr_shader.c puts a lightmap stage second).
    const bool swap = stages[0].source == Q3Stage::Source::lightmap;
    std::vector<TextureLayer> a = stage_layers(stages[swap ? 1 : 0], textures);
    std::vector<TextureLayer> b = stage_layers(stages[swap ? 0 : 1], textures);
    for (TextureLayer& l : b) l.combine = combine;
    a.insert(a.end(), b.begin(), b.end());
    Pass p = stage_pass(stages[0], std::move(a));
    p.src = src;
    p.dst = dst;
    p.depth_write = stages[0].depth_write;
    out.passes.push_back(std::move(p));
    out.collapsed = 1;
    first = 2;
  }
  for (size_t s = first; s < stages.size(); ++s) out.passes.push_back(stage_pass(stages[s], stage_layers(stages[s], textures)));
  if (out.passes.empty()) out.passes.push_back(Pass{});  // a shader without stages draws white
  // A pass's first layer starts its colour, so its combine means nothing;
  // it is modulate everywhere (a collapse after a white stage 0 would
  // otherwise leave stage 1's add there).
  for (Pass& p : out.passes)
    if (!p.layers.empty()) p.layers.front().combine = Combine::modulate;
  return out;
}

}  // namespace oovr
