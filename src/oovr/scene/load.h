// Finding scenes by name, through the registered scene sources
// (scene/source.h): built-in scenes, model files, installed game levels.
#pragma once

#include <string>
#include <vector>

#include "oovr/scene/scene.h"
#include "oovr/scene/source.h"

namespace oovr {

// Every scene `load_scene` accepts by name, source by source.
std::vector<SceneListing> list_scenes();

// A built-in scene name, a path to a model file, or "prefix:NAME?options"
// for a registered source. Throws Error saying what is wrong (unknown name,
// missing or bad file, bad option).
Scene load_scene(const std::string& spec);

// When `spec` names a scene of a source whose data is not installed: a
// message saying so and how to install it; else empty.
std::string scene_data_missing(const std::string& spec);

// A path of `frames` poses circling the box [lo, hi], looking at its centre
// from a little above; near and far planes sized to the box.
CameraPath orbit_camera_path(Vec3 lo, Vec3 hi, int frames);
// 120 frames of that path around the bounds of the scene's drawn objects.
CameraPath orbit_camera_around(const Scene& s);

}  // namespace oovr
