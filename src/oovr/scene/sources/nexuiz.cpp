// The "nexuiz:" scene source: Nexuiz 2.5 (Debian's nexuiz-data), drawn as
// DarkPlaces draws it.
#include "oovr/scene/sources/nexuiz.h"

#include <cstdlib>

namespace oovr {

std::string nexuiz_directory() {
  if (const char* d = std::getenv("OOVR_NEXUIZ_DIR"); d && *d) return d;
  return "/usr/share/games/nexuiz/data";
}

Q3Game nexuiz_game() { return {"nexuiz", "Nexuiz", nexuiz_directory(), Q3Engine::darkplaces}; }

std::vector<std::string> list_nexuiz_maps() { return list_q3_maps(nexuiz_game()); }

namespace {

const SceneSources::Add reg("nexuiz",
                            {"nexuiz", "nexuiz:MAP", true, 0, [] { return q3_listings(nexuiz_game(), "nexuiz"); }, nullptr,
                             [](const std::string& spec, const std::string& map, const SceneOptions& options) {
                               return load_q3_level(nexuiz_game(), map, parse_q3_level_options(spec, options));
                             },
                             nexuiz_directory});

}  // namespace
}  // namespace oovr
