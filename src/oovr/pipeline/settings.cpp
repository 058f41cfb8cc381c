#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/pipeline/pipeline.h"

namespace oovr {

const char* texture_format_name(TextureFormat f) {
  switch (f) {
    case TextureFormat::rgba8: return "rgba8";
    case TextureFormat::bc1: return "bc1";
    case TextureFormat::bc3: return "bc3";
    case TextureFormat::bc: return "bc";
  }
  return "?";
}

TextureFormat parse_texture_format(const std::string& name) {
  for (TextureFormat f : {TextureFormat::rgba8, TextureFormat::bc1, TextureFormat::bc3, TextureFormat::bc})
    if (name == texture_format_name(f)) return f;
  throw Error("unknown texture format '" + name + "': expected rgba8, bc1, bc3 or bc");
}

void PipelineSettings::validate() const {
  if (max_anisotropy < 1 || max_anisotropy > 16)
    throw Error("max_anisotropy must be from 1 to 16, not " + std::to_string(max_anisotropy));
  if (line_bytes < 32 || line_bytes > 1024 || (line_bytes & (line_bytes - 1)) != 0)
    throw Error("line_bytes must be a power of two from 32 to 1024, not " + std::to_string(line_bytes));
}

PipelineSettings PipelineSettings::from_config(const Config& c) {
  PipelineSettings s;
  s.texture_format = parse_texture_format(
      c.get_choice("pipeline.texture_format", texture_format_name(s.texture_format), {"rgba8", "bc1", "bc3", "bc"}));
  return s;
}

namespace {

const ConfigSections::Add reg(
    "pipeline", {"how the functional pipeline stores textures",
                 [](const Config& c) { (void)PipelineSettings::from_config(c); },
                 {{"pipeline.texture_format",
                   "texture storage: rgba8, bc1, bc3, or bc (BC1 opaque, BC3 with alpha, as the games shipped them)"}}});

}  // namespace

}  // namespace oovr
