// Model files as a scene source (formats/model.h: OBJ, glTF 2, GLB and PLY
// through assimp, AC3D through oovr's own reader).
#include <filesystem>

#include "oovr/scene/formats/model.h"
#include "oovr/scene/source.h"

namespace oovr {
namespace {

// Model files are asked after the built-in scenes: any name that is an
// existing file (a path may contain ':', so this runs when no prefix claimed
// it), or that names a model file by its extension, so that a missing one
// is "no such file", not an unknown scene.
const SceneSources::Add reg(
    "file", {"model file", "a model file path (OBJ, glTF, GLB, PLY, AC3D)", false, 10, nullptr,
             [](const std::string& name) {
               std::error_code ec;
               return std::filesystem::exists(name, ec) || is_model_path(name);
             },
             [](const std::string&, const std::string& path, const SceneOptions&) { return load_model_file(path); }, nullptr});

}  // namespace
}  // namespace oovr
