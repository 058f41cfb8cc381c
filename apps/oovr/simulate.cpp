// oovr simulate / oovr compare: render a scene's frames once, replay them
// through one or several schemes, and print (or write as JSON) the results.
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"
#include "oovr/run/result_images.h"
#include "oovr/run/result_json.h"
#include "oovr/run/result_text.h"
#include "oovr/run/simulation.h"
#include "oovr/run/timeline.h"
#include "progress.h"

namespace oovr::cli {
namespace {

void write_json(const std::string& path, const nlohmann::ordered_json& j) {
  write_output_file(path, j.dump(2) + "\n", "JSON output");
}

SimulationRequest request_of(const SimulateArgs& a) {
  SimulationRequest r;
  r.scene = a.scene;
  r.rig = a.eye_resolution.empty() ? parse_frame_resolution(a.resolution) : parse_eye_resolution(a.eye_resolution);
  r.frame = a.frame;
  r.frames = a.frames;
  r.aniso = a.aniso;
  r.use_cache = !a.no_cache;
  return r;
}

nlohmann::ordered_json document(const SimulateArgs& a, const Simulation& s, const Config& config) {
  return results_document(a.command, s.window->scene->name, s.frame, s.frames, s.window->rig, config, s.results, s.window->notes);
}

}  // namespace

Config machine_config(const std::string& file, const std::vector<std::string>& settings) {
  Config c = file.empty() ? Config{} : Config::from_toml_file(file);
  for (const auto& s : settings) c.set(s);
  return c;
}

int simulate(const SimulateArgs& a) {
  // Outputs are checked before any work, and may not share a path.
  OutputPaths outputs;
  if (!a.json.empty()) {
    check_output_path(a.json, "JSON output");
    outputs.claim(a.json, "JSON output (--json)");
  }
  if (!a.gpm_image.empty()) {
    check_image_path(a.gpm_image);
    outputs.claim(a.gpm_image, "GPM image (--gpm-image)");
  }
  if (!a.traffic_image.empty()) {
    check_image_path(a.traffic_image);
    outputs.claim(a.traffic_image, "traffic image (--traffic-image)");
  }
  if (!a.timeline.empty()) {
    check_output_path(a.timeline, "timeline (--timeline)");
    outputs.claim(a.timeline, "timeline (--timeline)");
  }
  const Config config = machine_config(a.config, a.settings);
  SimulationRequest r = request_of(a);
  r.need_first_image = !a.gpm_image.empty() || !a.traffic_image.empty();
  r.timeline = !a.timeline.empty();
  StatusLine status;
  if (status.on()) r.progress = [&](const std::string& what) { status.show(what); };
  const Simulation s = run_simulation(r, {find_scheme(a.scheme)}, config);
  status.clear();
  fmt::print("{}{}", simulation_text(s), timing_text(s));
  if (!a.json.empty()) write_json(a.json, document(a, s, config));
  const FrameOutput& first = s.window->outputs.front();
  if (!a.gpm_image.empty()) write_image(gpm_image(first, s.results.front()), a.gpm_image);
  if (!a.traffic_image.empty()) write_image(traffic_image(first, s.results.front()), a.traffic_image);
  if (!a.timeline.empty()) {
    const TimelineText t = timeline_json(s.results.front(), a.timeline_events);
    write_output_file(a.timeline, t.json, "timeline");
    fmt::print("timeline: {} units in {}{} (open it in ui.perfetto.dev or chrome://tracing)\n", t.units, a.timeline,
               t.omitted ? fmt::format(", {} later ones left out (--timeline-events)", t.omitted) : std::string());
  }
  return 0;
}

int compare(const SimulateArgs& a, const std::vector<std::string>& schemes) {
  if (!a.json.empty()) check_output_path(a.json, "JSON output");
  const Config config = machine_config(a.config, a.settings);
  std::vector<SchemeRef> refs;
  for (const auto& n : schemes) refs.push_back(find_scheme(n));
  SimulationRequest r = request_of(a);
  StatusLine status;
  if (status.on()) r.progress = [&](const std::string& what) { status.show(what); };
  const Simulation s = run_simulation(r, refs, config);
  status.clear();
  fmt::print("{}{}", comparison_text(s), timing_text(s));
  if (!a.json.empty()) write_json(a.json, document(a, s, config));
  return 0;
}

}  // namespace oovr::cli
