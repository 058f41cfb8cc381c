#include "oovr/experiments/result_json.h"

#include "oovr/core/version.h"

namespace oovr {

nlohmann::ordered_json results_header(const std::string& command) {
  nlohmann::ordered_json j;
  j["schema"] = "oovr.results";
  j["schema_version"] = kResultsSchemaVersion;
  j["oovr"] = {{"version", version()}, {"commit", git_commit()}};
  j["command"] = command;
  return j;
}

nlohmann::ordered_json to_json(const std::map<std::string, Config::Entry>& config) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [key, e] : config) {
    nlohmann::ordered_json x;
    x["value"] = e.value;
    if (e.base) {
      x["base"] = *e.base;
      if (!e.unit.empty()) x["unit"] = e.unit;
    }
    x["source"] = e.source;
    j[key] = x;
  }
  return j;
}

nlohmann::ordered_json to_json(const SchemeResult& r) {
  nlohmann::ordered_json j;
  j["scheme"] = r.scheme;
  j["gpms"] = r.gpms;
  j["frame_latency_cycles"] = r.frame_latency_cycles();
  j["frame_latency_ms"] = r.frame_latency_s * 1e3;
  j["throughput_fps"] = r.throughput_fps;
  j["frames_in_flight"] = r.frames_in_flight;
  j["inter_gpm_bytes"] = r.total_inter_gpm_bytes();
  nlohmann::ordered_json cat = nlohmann::ordered_json::object();
  for (int c = 0; c < kCategories; ++c) cat[category_name(Category(c))] = r.inter_gpm_bytes[size_t(c)];
  j["inter_gpm_bytes_by_category"] = cat;
  j["local_dram_bytes"] = r.local_dram_bytes;
  j["footprint_bytes"] = r.footprint_bytes;
  nlohmann::ordered_json busy = nlohmann::ordered_json::array();
  for (double b : r.gpm_busy_s) busy.push_back(b * r.frequency_hz);
  j["gpm_busy_cycles"] = busy;
  j["best_to_worst"] = r.best_to_worst();
  j["draws_received"] = r.draws;
  j["vertices_transformed"] = r.vertices;
  j["work_units"] = r.units;
  j["notes"] = r.notes;
  j["frame_latency_cycles_per_frame"] = nlohmann::ordered_json::array();
  for (double l : r.frame_latencies_s) j["frame_latency_cycles_per_frame"].push_back(l * r.frequency_hz);
  j["config"] = to_json(r.config);
  return j;
}

}  // namespace oovr
