// Scene sources: where `load_scene` finds a scene by name.
//
// A source is one file under scene/sources/ with one registration line:
//
//   static const SceneSources::Add reg("oa", {"openarena", "oa:MAP", true, 0, list, nullptr, load, directory});
//
// A source registered under a prefix ("oa", "nexuiz", "torcs") answers
// names of the form "prefix:NAME?key=value&...": load_scene splits the
// prefix and the options off and hands the rest over. A source with an empty
// prefix is asked, in order of `order`, about every name no prefix claimed
// (built-in scenes, model files). load.cpp knows no source by name, so a new
// game is one new file.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "oovr/core/registry.h"
#include "oovr/scene/scene.h"

namespace oovr {

struct SceneListing {
  std::string name;  // what load_scene accepts, e.g. "oa:oa_dm4"
  std::string kind;  // the source's kind, e.g. "openarena"
  std::string description;
};

// "key=value" options after a scene name's '?'.
using SceneOptions = std::map<std::string, std::string>;

struct SceneSource {
  std::string kind;      // "built-in", "openarena", ... (the listing's kind)
  std::string form;      // how its names look, for messages: "oa:MAP"
  bool prefixed = true;  // false: asked about names no prefix claimed
  int order = 0;         // unprefixed sources are asked in increasing order
  // The scenes this source can load now (installed data), sorted.
  std::function<std::vector<SceneListing>()> list;
  // For unprefixed sources: whether this name is one of theirs.
  std::function<bool(const std::string& name)> claims;
  // Loads one scene. `spec` is the whole name as the user wrote it (for
  // messages), `name` what follows the prefix without the options. Throws
  // Error naming what is wrong (unknown name, bad option, bad file).
  std::function<Scene(const std::string& spec, const std::string& name, const SceneOptions& options)> load;
  // The directory its data is installed in (game sources), for "not
  // installed" messages and skipped tests; nullptr for sources without data.
  std::function<std::string()> data_directory;
};

using SceneSources = Registry<SceneSource>;

// A whole-number scene option; Error naming key, value and spec otherwise.
int scene_int_option(const std::string& key, const std::string& value, const std::string& spec);
// Error for an option the source does not take, naming the ones it does.
[[noreturn]] void unknown_scene_option(const std::string& key, const std::string& spec, const std::string& accepted);

}  // namespace oovr
