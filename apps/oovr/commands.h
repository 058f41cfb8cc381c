// The CLI's commands that replay traces through schemes (simulate.cpp).
#pragma once

#include <string>
#include <vector>

#include "oovr/core/config.h"

namespace oovr::cli {

struct SimulateArgs {
  std::string scene;
  std::string scheme;
  int frame = 0;
  int frames = 0;  // 0: one per GPM
  std::string resolution = "1280x1024";
  std::string eye_resolution;
  int aniso = 16;
  std::string config;
  std::vector<std::string> settings;
  std::string json, gpm_image, traffic_image;
  bool no_cache = false;
};

// A preset (or the built-in defaults) with --set overrides.
Config machine_config(const std::string& file, const std::vector<std::string>& settings);
int simulate(const SimulateArgs& a);
int compare(const SimulateArgs& a, const std::vector<std::string>& schemes);

}  // namespace oovr::cli
