// The built-in procedural scenes (scene/builtin/) as a scene source: their
// bare names, asked first.
#include "oovr/scene/builtin.h"
#include "oovr/scene/source.h"

namespace oovr {
namespace {

std::vector<SceneListing> list() {
  std::vector<SceneListing> out;
  for (const auto& name : BuiltinScenes::names()) out.push_back({name, "built-in", BuiltinScenes::find(name)->description});
  return out;
}

const SceneSources::Add reg("built-in", {"built-in", "a built-in scene", false, 0, list,
                                         [](const std::string& name) { return BuiltinScenes::find(name) != nullptr; },
                                         [](const std::string&, const std::string& name, const SceneOptions&) {
                                           return BuiltinScenes::find(name)->make();
                                         },
                                         nullptr});

}  // namespace
}  // namespace oovr
