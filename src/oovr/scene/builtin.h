// Built-in procedural scenes: generated in code, deterministic, no data files.
// Each lives in scene/builtin/<name>.cpp with one registration line.
#pragma once

#include <functional>
#include <string>

#include "oovr/core/registry.h"
#include "oovr/scene/scene.h"

namespace oovr {

struct BuiltinScene {
  std::string description;
  std::function<Scene()> make;
};

using BuiltinScenes = Registry<BuiltinScene>;

constexpr const char* kDefaultScene = "courtyard";

}  // namespace oovr
