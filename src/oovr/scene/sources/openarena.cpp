// The "oa:" scene source: OpenArena (Debian's openarena-data), drawn as
// ioquake3 draws it.
#include "oovr/scene/sources/openarena.h"

#include <cstdlib>

namespace oovr {

std::string openarena_directory() {
  if (const char* d = std::getenv("OOVR_OPENARENA_DIR"); d && *d) return d;
  return "/usr/share/games/openarena/baseoa";
}

Q3Game openarena_game() { return {"oa", "OpenArena", openarena_directory(), Q3Engine::ioquake3}; }

std::vector<std::string> list_openarena_maps() { return list_q3_maps(openarena_game()); }

namespace {

const SceneSources::Add reg("oa",
                            {"openarena", "oa:MAP", true, 0, [] { return q3_listings(openarena_game(), "openarena"); }, nullptr,
                             [](const std::string& spec, const std::string& map, const SceneOptions& options) {
                               return load_q3_level(openarena_game(), map, parse_q3_level_options(spec, options));
                             },
                             openarena_directory});

}  // namespace
}  // namespace oovr
