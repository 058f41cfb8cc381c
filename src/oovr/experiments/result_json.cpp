#include "oovr/experiments/result_json.h"

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
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

nlohmann::ordered_json base_value(const Config::Entry& e) {
  return e.base ? nlohmann::ordered_json(*e.base) : nlohmann::ordered_json(e.value);
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

namespace {

// The memory system's statistics (docs/results.md, "memory"): counts, the
// share of accesses each level served, each link's bytes and utilisation
// (bytes per frame at the run's frame rate over the link's bandwidth), the
// GPM-to-GPM matrix and each GPM's DRAM bytes.
nlohmann::ordered_json memory_json(const SchemeResult& r) {
  const MemoryStats& m = r.memory;
  nlohmann::ordered_json j;
  j["accesses"] = m.accesses;
  j["l1_hits"] = m.l1_hits;
  j["l2_hits"] = m.l2_hits;
  j["remote_hits"] = m.remote_hits;
  j["home_l2_hits"] = m.home_l2_hits;
  j["dram_lines"] = m.dram_lines;
  const auto share = [&](uint64_t v) { return m.accesses ? double(v) / double(m.accesses) : 0.0; };
  j["served_share"] = {{"l1", share(m.l1_hits)},
                       {"l2", share(m.l2_hits)},
                       {"remote_cache", share(m.remote_hits)},
                       {"home_l2", share(m.home_l2_hits)},
                       {"dram", share(m.dram_lines)}};
  const auto bw = r.config.find("link.bandwidth");
  const double link_bandwidth = bw != r.config.end() && bw->second.base ? *bw->second.base : 0;
  nlohmann::ordered_json links = nlohmann::ordered_json::array();
  for (size_t l = 0; l < m.link_bytes.size(); ++l) {
    nlohmann::ordered_json x;
    x["link"] = l < m.link_names.size() ? m.link_names[l] : std::to_string(l);
    x["bytes"] = m.link_bytes[l];
    x["utilisation"] = link_bandwidth > 0 ? double(m.link_bytes[l]) * r.throughput_fps / link_bandwidth : 0.0;
    links.push_back(x);
  }
  j["links"] = links;
  nlohmann::ordered_json matrix = nlohmann::ordered_json::array();
  const size_t n = size_t(r.gpms);
  for (size_t from = 0; from < n && (from + 1) * n <= m.gpm_to_gpm_bytes.size(); ++from) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (size_t to = 0; to < n; ++to) row.push_back(m.gpm_to_gpm_bytes[from * n + to]);
    matrix.push_back(row);
  }
  j["gpm_to_gpm_bytes"] = matrix;
  j["dram_bytes"] = m.dram_bytes;
  return j;
}

}  // namespace

nlohmann::ordered_json to_json(const SchemeResult& r) {
  nlohmann::ordered_json j;
  j["scheme"] = r.scheme;
  j["gpms"] = r.gpms;
  j["frame_latency_cycles"] = r.frame_latency_cycles();
  j["frame_latency_ms"] = r.frame_latency_s * 1e3;
  j["frame_latency_s"] = r.frame_latency_s;  // exact, for scheme_result_from_json
  j["frame_latencies_s"] = r.frame_latencies_s;
  j["frequency_hz"] = r.frequency_hz;
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
  j["gpm_busy_s"] = r.gpm_busy_s;
  j["best_to_worst"] = r.best_to_worst();
  j["draws_received"] = r.draws;
  j["vertices_transformed"] = r.vertices;
  j["work_units"] = r.units;
  j["covered_fragments"] = r.covered_fragments;
  j["notes"] = r.notes;
  // The scheme's own figures (OO-VR's batches, moved chunks, predictor).
  nlohmann::ordered_json own = nlohmann::ordered_json::object();
  for (const SchemeMetric& m : r.metrics) {
    own[m.name] = {{"value", m.value}};
    if (!m.unit.empty()) own[m.name]["unit"] = m.unit;
  }
  j["scheme_metrics"] = own;
  j["memory"] = memory_json(r);
  j["frame_latency_cycles_per_frame"] = nlohmann::ordered_json::array();
  for (double l : r.frame_latencies_s) j["frame_latency_cycles_per_frame"].push_back(l * r.frequency_hz);
  j["config"] = to_json(r.config);
  return j;
}

SchemeResult scheme_result_from_json(const nlohmann::ordered_json& j) {
  try {
    SchemeResult r;
    r.scheme = j.at("scheme").get<std::string>();
    r.gpms = j.at("gpms").get<int>();
    r.frequency_hz = j.at("frequency_hz").get<double>();
    r.frame_latency_s = j.at("frame_latency_s").get<double>();
    r.frame_latencies_s = j.at("frame_latencies_s").get<std::vector<double>>();
    r.throughput_fps = j.at("throughput_fps").get<double>();
    r.frames_in_flight = j.at("frames_in_flight").get<int>();
    r.gpm_busy_s = j.at("gpm_busy_s").get<std::vector<double>>();
    for (int c = 0; c < kCategories; ++c)
      r.inter_gpm_bytes[size_t(c)] = j.at("inter_gpm_bytes_by_category").at(category_name(Category(c))).get<uint64_t>();
    r.local_dram_bytes = j.at("local_dram_bytes").get<uint64_t>();
    r.footprint_bytes = j.at("footprint_bytes").get<uint64_t>();
    r.covered_fragments = j.at("covered_fragments").get<uint64_t>();
    r.vertices = j.at("vertices_transformed").get<uint64_t>();
    r.draws = j.at("draws_received").get<uint64_t>();
    r.units = j.at("work_units").get<uint64_t>();
    r.notes = j.at("notes").get<std::vector<std::string>>();
    for (const auto& [name, m] : j.at("scheme_metrics").items())
      r.metrics.push_back({name, m.at("value").get<double>(), m.value("unit", "")});
    const auto& mem = j.at("memory");
    r.memory.accesses = mem.at("accesses").get<uint64_t>();
    r.memory.l1_hits = mem.at("l1_hits").get<uint64_t>();
    r.memory.l2_hits = mem.at("l2_hits").get<uint64_t>();
    r.memory.remote_hits = mem.at("remote_hits").get<uint64_t>();
    r.memory.home_l2_hits = mem.at("home_l2_hits").get<uint64_t>();
    r.memory.dram_lines = mem.at("dram_lines").get<uint64_t>();
    for (const auto& l : mem.at("links")) {
      r.memory.link_names.push_back(l.at("link").get<std::string>());
      r.memory.link_bytes.push_back(l.at("bytes").get<uint64_t>());
    }
    for (const auto& row : mem.at("gpm_to_gpm_bytes"))
      for (const auto& b : row) r.memory.gpm_to_gpm_bytes.push_back(b.get<uint64_t>());
    r.memory.dram_bytes = mem.at("dram_bytes").get<std::vector<uint64_t>>();
    for (const auto& [key, e] : j.at("config").items()) {
      Config::Entry x;
      x.value = e.at("value").get<std::string>();
      x.source = e.at("source").get<std::string>();
      if (e.contains("base")) x.base = e.at("base").get<double>();
      x.unit = e.value("unit", "");
      r.config[key] = x;
    }
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("a run's result that is not oovr's: ") + e.what());
  }
}

nlohmann::ordered_json results_document(const std::string& command, const std::string& scene, int frame, int frames,
                                        const StereoRig& rig, const Config& config, const std::vector<SchemeResult>& results,
                                        const std::vector<std::string>& trace_notes) {
  nlohmann::ordered_json j = results_header(command);
  j["scene"] = scene;
  j["frame"] = frame;
  j["frames"] = frames;
  j["resolution"] = std::to_string(rig.frame_width()) + "x" + std::to_string(rig.frame_height());
  check_config(config);  // reads every key, so that all are described
  j["config"] = to_json(config.entries());
  const SchemeResult* base = nullptr;
  for (const auto& r : results)
    if (r.scheme == "baseline") base = &r;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const auto& r : results) {
    nlohmann::ordered_json x = to_json(r);
    if (base) {
      x["speedup_vs_baseline"] = base->frame_latency_s / r.frame_latency_s;
      x["throughput_vs_baseline"] = r.throughput_fps / base->throughput_fps;
      x["traffic_vs_baseline"] =
          base->total_inter_gpm_bytes() ? double(r.total_inter_gpm_bytes()) / double(base->total_inter_gpm_bytes()) : 0.0;
    }
    runs.push_back(x);
  }
  j["runs"] = runs;
  j["trace_notes"] = trace_notes;
  return j;
}

}  // namespace oovr
