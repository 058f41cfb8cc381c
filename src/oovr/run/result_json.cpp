#include "oovr/run/result_json.h"

#include <cmath>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/version.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/run/result_metrics.h"

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

// A count the memory system reported (check_scheme_result makes sure each
// is a whole number from 0 up); 0 when it did not report it.
uint64_t count_at(const SchemeResult& r, const std::string& location, const std::string& name) {
  const Stat* s = r.stats.find(location, name);
  return s ? uint64_t(s->value) : 0;
}

std::string gpm(size_t g) { return "gpm[" + std::to_string(g) + "]"; }

const char* const kLevels[][2] = {
    {"l1", "l1_hits"}, {"l2", "l2_hits"}, {"remote_cache", "remote_hits"}, {"home_l2", "home_l2_hits"}, {"dram", "dram_lines"}};

// The memory system's statistics (docs/results.md, "memory"): counts, the
// share of accesses each level served, each link's bytes and utilisation
// (bytes per frame at the run's frame rate over the link's bandwidth), the
// GPM-to-GPM matrix and each GPM's DRAM bytes.
nlohmann::ordered_json memory_json(const SchemeResult& r) {
  nlohmann::ordered_json j;
  const uint64_t accesses = count_at(r, "memory", "accesses");
  j["accesses"] = accesses;
  for (const auto& [level, field] : kLevels) j[field] = count_at(r, level, "served");
  nlohmann::ordered_json share;
  for (const auto& [level, field] : kLevels)
    share[level] = accesses ? double(count_at(r, level, "served")) / double(accesses) : 0.0;
  j["served_share"] = share;
  nlohmann::ordered_json links = nlohmann::ordered_json::array();
  for (const Stat& s : r.stats.all())
    if (s.name == "bytes" && s.location.rfind("link[", 0) == 0) {
      nlohmann::ordered_json x;
      x["link"] = link_name_at(s.location);
      x["bytes"] = uint64_t(s.value);
      const double u = utilisation_of(r, s.location);
      x["utilisation"] = std::isnan(u) ? 0.0 : u;
      links.push_back(x);
    }
  j["links"] = links;
  nlohmann::ordered_json matrix = nlohmann::ordered_json::array();
  const size_t n = size_t(r.gpms);
  for (size_t from = 0; from < n; ++from) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (size_t to = 0; to < n; ++to) row.push_back(from == to ? 0 : count_at(r, gpm(from) + "->" + gpm(to), "bytes"));
    matrix.push_back(row);
  }
  j["gpm_to_gpm_bytes"] = matrix;
  nlohmann::ordered_json dram = nlohmann::ordered_json::array();
  for (size_t g = 0; g < n; ++g) dram.push_back(count_at(r, gpm(g) + ".dram", "bytes"));
  j["dram_bytes"] = dram;
  return j;
}

// The memory section of a result written before results carried their
// statistics (no "stats"): its counts as the memory system reports them,
// and each link's utilisation as it was stored.
void stats_from_memory_json(const nlohmann::ordered_json& mem, int gpms, Stats& out) {
  out.count("memory", "accesses", json_count(mem.at("accesses"), "accesses"));
  for (const auto& [level, field] : kLevels) out.count(level, "served", json_count(mem.at(field), field));
  const auto& dram = mem.at("dram_bytes");
  if (!dram.is_array() || dram.size() != size_t(gpms)) throw Error("a run's result with DRAM bytes of the wrong count");
  for (size_t g = 0; g < dram.size(); ++g) out.count(gpm(g) + ".dram", "bytes", json_count(dram[g], "DRAM bytes"), "B");
  for (const auto& l : mem.at("links")) {
    const std::string name = l.at("link").get<std::string>();
    const std::string at = link_location_of(name);
    if (at.empty()) throw Error("a run's result with a link named '" + name + "'");
    out.count(at, "bytes", json_count(l.at("bytes"), "bytes"), "B");
    out.add(at, "utilisation", json_finite(l.at("utilisation"), "a link's utilisation"));
  }
  const auto& matrix = mem.at("gpm_to_gpm_bytes");
  if (!matrix.is_array() || matrix.size() != size_t(gpms))
    throw Error("a run's result with a GPM-to-GPM matrix of the wrong size");
  for (size_t from = 0; from < matrix.size(); ++from) {
    if (!matrix[from].is_array() || matrix[from].size() != size_t(gpms))
      throw Error("a run's result with a GPM-to-GPM matrix of the wrong size");
    for (size_t to = 0; to < size_t(gpms); ++to) {
      const uint64_t b = json_count(matrix[from][to], "GPM-to-GPM bytes");
      if (from != to) out.count(gpm(from) + "->" + gpm(to), "bytes", b, "B");
    }
  }
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
  // The memory system's energy per frame, in joules (result_metrics.h,
  // energy_of); absent from a result stored before oovr counted it.
  if (const Energy e = energy_of(r); e.known)
    j["energy_j"] = {{"total", e.total()}, {"caches", e.caches}, {"dram", e.dram}, {"links", e.links}};
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
  for (const Stat& m : r.stats.all())
    if (m.location == r.scheme) {
      own[m.name] = {{"value", m.value}};
      if (!m.unit.empty()) own[m.name]["unit"] = m.unit;
    }
  j["scheme_metrics"] = own;
  j["memory"] = memory_json(r);
  j["frame_latency_cycles_per_frame"] = nlohmann::ordered_json::array();
  for (double l : r.frame_latencies_s) j["frame_latency_cycles_per_frame"].push_back(l * r.frequency_hz);
  j["config"] = to_json(r.config);
  // Every statistic, as the database's metrics rows have them:
  // [location, name, value, unit] (what scheme_result_from_json reads).
  nlohmann::ordered_json stats = nlohmann::ordered_json::array();
  for (const Stat& s : r.stats.all()) stats.push_back({s.location, s.name, s.value, s.unit});
  j["stats"] = stats;
  return j;
}

int64_t json_whole(const nlohmann::ordered_json& v, int64_t lo, int64_t hi, const std::string& what) {
  bool ok = false;
  int64_t x = 0;
  if (v.is_number_unsigned()) {
    ok = v.get<uint64_t>() <= uint64_t(INT64_MAX);
    x = ok ? int64_t(v.get<uint64_t>()) : 0;
  } else if (v.is_number_integer()) {
    ok = true;
    x = v.get<int64_t>();
  }
  if (!ok || x < lo || x > hi)
    throw Error(what + " is " + v.dump() + ", not a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
  return x;
}

uint64_t json_count(const nlohmann::ordered_json& v, const std::string& what) {
  if (!v.is_number_unsigned()) throw Error(what + " is " + v.dump() + ", not a count (a whole number, 0 or more)");
  return v.get<uint64_t>();
}

double json_finite(const nlohmann::ordered_json& v, const std::string& what) {
  if (!v.is_number() || !std::isfinite(v.get<double>())) throw Error(what + " is " + v.dump() + ", not a finite number");
  return v.get<double>();
}

SchemeResult scheme_result_from_json(const nlohmann::ordered_json& j) {
  try {
    SchemeResult r;
    r.scheme = j.at("scheme").get<std::string>();
    r.gpms = int(json_whole(j.at("gpms"), 1, kMaxGpms, "gpms"));
    r.frequency_hz = json_finite(j.at("frequency_hz"), "frequency_hz");
    r.frame_latency_s = json_finite(j.at("frame_latency_s"), "frame_latency_s");
    for (const auto& l : j.at("frame_latencies_s")) r.frame_latencies_s.push_back(json_finite(l, "a frame latency"));
    r.throughput_fps = json_finite(j.at("throughput_fps"), "throughput_fps");
    r.frames_in_flight = int(json_whole(j.at("frames_in_flight"), 1, 1 << 20, "frames_in_flight"));
    for (const auto& b : j.at("gpm_busy_s")) r.gpm_busy_s.push_back(json_finite(b, "a GPM's busy time"));
    for (int c = 0; c < kCategories; ++c)
      r.inter_gpm_bytes[size_t(c)] =
          json_count(j.at("inter_gpm_bytes_by_category").at(category_name(Category(c))), "inter_gpm_bytes_by_category");
    r.local_dram_bytes = json_count(j.at("local_dram_bytes"), "local_dram_bytes");
    r.footprint_bytes = json_count(j.at("footprint_bytes"), "footprint_bytes");
    r.covered_fragments = json_count(j.at("covered_fragments"), "covered_fragments");
    r.vertices = json_count(j.at("vertices_transformed"), "vertices_transformed");
    r.draws = json_count(j.at("draws_received"), "draws_received");
    r.units = json_count(j.at("work_units"), "work_units");
    r.notes = j.at("notes").get<std::vector<std::string>>();
    if (j.contains("stats")) {
      // Statistics are rows here; their merge rules matter only before a
      // window is merged, which a result read back is not.
      for (const auto& x : j.at("stats")) {
        if (!x.is_array() || x.size() != 4) throw Error("a statistic that is not [location, name, value, unit]");
        r.stats.add(x.at(0).get<std::string>(), x.at(1).get<std::string>(), json_finite(x.at(2), "a statistic's value"),
                    x.at(3).get<std::string>());
      }
    } else {
      stats_from_memory_json(j.at("memory"), r.gpms, r.stats);
      for (const auto& [name, m] : j.at("scheme_metrics").items())
        r.stats.add(r.scheme, name, json_finite(m.at("value"), name), m.value("unit", ""));
    }
    for (const auto& [key, e] : j.at("config").items()) {
      Config::Entry x;
      x.value = e.at("value").get<std::string>();
      x.source = e.at("source").get<std::string>();
      if (e.contains("base")) x.base = json_finite(e.at("base"), key);
      x.unit = e.value("unit", "");
      r.config[key] = x;
    }
    check_scheme_result(r);
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("a run's result that is not oovr's: ") + e.what());
  }
}

nlohmann::ordered_json stored_result_json(const SchemeResult& r) {
  nlohmann::ordered_json j = to_json(r);
  j.erase("stats");
  j.erase("memory");
  j.erase("scheme_metrics");
  j.erase("energy_j");  // the metrics rows' formulas give it back
  return j;
}

SchemeResult scheme_result_from_stored(const nlohmann::ordered_json& result, const std::vector<Metric>& rows) {
  if (!result.is_object() || result.contains("stats") || result.contains("memory")) return scheme_result_from_json(result);
  nlohmann::ordered_json j = result;
  nlohmann::ordered_json stats = nlohmann::ordered_json::array();
  for (const Metric& m : rows)
    if (is_stat_row(m)) stats.push_back({m.location, m.metric, m.value, m.unit});
  j["stats"] = std::move(stats);
  return scheme_result_from_json(j);
}

void check_scheme_result(const SchemeResult& r) {
  const auto bad = [](const std::string& what) { throw Error("a run's result that cannot be: " + what); };
  const auto positive = [&](double v, const std::string& what) {
    if (!(std::isfinite(v) && v > 0)) bad(what + " is " + format_number(v) + ", not a positive number");
  };
  if (r.gpms < 1 || r.gpms > kMaxGpms) bad(std::to_string(r.gpms) + " GPMs");
  positive(r.frequency_hz, "the frequency");
  positive(r.frame_latency_s, "the frame latency");
  positive(r.throughput_fps, "the throughput");
  if (r.frame_latencies_s.empty()) bad("no frame latencies");
  for (double l : r.frame_latencies_s) positive(l, "a frame's latency");
  if (r.frames_in_flight < 1) bad(std::to_string(r.frames_in_flight) + " frames in flight");
  if (r.gpm_busy_s.size() != size_t(r.gpms)) bad("busy times of " + std::to_string(r.gpm_busy_s.size()) + " GPMs");
  for (double b : r.gpm_busy_s)
    if (!(std::isfinite(b) && b >= 0)) bad("a GPM busy for " + format_number(b) + " s");
  // The memory system's counts that JSON writes as whole numbers.
  const auto count = [&](const std::string& location, const std::string& name) {
    const Stat* s = r.stats.find(location, name);
    if (!s) bad("no statistic '" + location + " " + name + "'");
    if (!(s->value >= 0 && s->value < 0x1p64 && s->value == std::floor(s->value)))
      bad("statistic '" + location + " " + name + "' is " + format_number(s->value) + ", not a count");
  };
  count("memory", "accesses");
  for (const auto& [level, field] : kLevels) count(level, "served");
  for (int g = 0; g < r.gpms; ++g) {
    count(gpm(size_t(g)) + ".dram", "bytes");
    for (int to = 0; to < r.gpms; ++to)
      if (to != g) count(gpm(size_t(g)) + "->" + gpm(size_t(to)), "bytes");
  }
  for (const Stat& s : r.stats.all())
    if (s.name == "bytes" && s.location.rfind("link[", 0) == 0) count(s.location, "bytes");
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
