#include "oovr/run/result_metrics.h"

#include <cmath>

#include "oovr/memory/category.h"

namespace oovr {

namespace {

std::string gpm(size_t g) { return "gpm[" + std::to_string(g) + "]"; }

}  // namespace

double utilisation_of(const SchemeResult& r, const std::string& location) {
  const Stat* capacity = r.stats.find(location, "capacity");
  if (!capacity) {
    const Stat* stored = r.stats.find(location, "utilisation");
    return stored ? stored->value : std::nan("");
  }
  const Stat* used = r.stats.find(location, "bytes");
  if (!used) used = r.stats.find(location, "used");
  return used && capacity->value > 0 ? used->value * r.throughput_fps / capacity->value : 0.0;
}

double energy_at(const SchemeResult& r, const std::string& location) {
  if (const Stat* per_lookup = r.stats.find(location, "energy_per_lookup")) {
    const Stat* lookups = r.stats.find(location, "lookups");
    return lookups ? lookups->value * per_lookup->value : 0.0;
  }
  if (const Stat* per_bit = r.stats.find(location, "energy_per_bit")) {
    const Stat* bytes = r.stats.find(location, "bytes");
    return bytes ? bytes->value * 8 * per_bit->value : 0.0;
  }
  return std::nan("");
}

Energy energy_of(const SchemeResult& r) {
  Energy e;
  for (const Stat& s : r.stats.all()) {
    if (s.name != "energy_per_lookup" && s.name != "energy_per_bit") continue;
    const double j = energy_at(r, s.location);
    e.known = true;
    if (s.name == "energy_per_lookup") e.caches += j;
    else if (s.location.rfind("link[", 0) == 0) e.links += j;
    else e.dram += j;
  }
  return e;
}

std::string link_name_at(const std::string& location) {
  const auto arrow = location.find("->");
  if (location.rfind("link[", 0) != 0 || location.back() != ']' || arrow == std::string::npos) return location;
  const auto node = [](const std::string& n) {
    return !n.empty() && n.find_first_not_of("0123456789") == std::string::npos ? "gpm" + n : n;
  };
  return node(location.substr(5, arrow - 5)) + "->" + node(location.substr(arrow + 2, location.size() - arrow - 3));
}

std::string link_location_of(const std::string& name) {
  const auto arrow = name.find("->");
  if (arrow == std::string::npos) return "";
  const auto node = [](const std::string& n) { return n.rfind("gpm", 0) == 0 ? n.substr(3) : n; };
  return "link[" + node(name.substr(0, arrow)) + "->" + node(name.substr(arrow + 2)) + "]";
}

std::vector<Metric> metrics_of(const SchemeResult& r) {
  std::vector<Metric> out;
  const auto add = [&](const std::string& location, const std::string& metric, double value, const std::string& unit) {
    out.push_back({location, metric, value, unit});
  };
  add("frame", "latency", r.frame_latency_s, "s");
  add("frame", "latency_cycles", r.frame_latency_cycles(), "cycles");
  add("frame", "throughput", r.throughput_fps, "frames/s");
  add("frame", "frames_in_flight", r.frames_in_flight, "");
  add("frame", "best_to_worst", r.best_to_worst(), "");
  add("frame", "inter_gpm_bytes", double(r.total_inter_gpm_bytes()), "B");
  for (int c = 0; c < kCategories; ++c)
    add("frame", std::string("inter_gpm_bytes.") + category_name(Category(c)), double(r.inter_gpm_bytes[size_t(c)]), "B");
  add("frame", "dram_bytes", double(r.local_dram_bytes), "B");
  add("frame", "footprint_bytes", double(r.footprint_bytes), "B");
  add("frame", "draws_received", double(r.draws), "");
  add("frame", "vertices_transformed", double(r.vertices), "");
  add("frame", "covered_fragments", double(r.covered_fragments), "");
  add("frame", "work_units", double(r.units), "");
  if (const Energy e = energy_of(r); e.known) {
    add("frame", "energy", e.total(), "J");
    add("frame", "energy.caches", e.caches, "J");
    add("frame", "energy.dram", e.dram, "J");
    add("frame", "energy.links", e.links, "J");
  }
  for (size_t k = 0; k < r.frame_latencies_s.size(); ++k)
    add("frame[" + std::to_string(k) + "]", "latency", r.frame_latencies_s[k], "s");
  for (size_t g = 0; g < r.gpm_busy_s.size(); ++g) add(gpm(g), "busy", r.gpm_busy_s[g], "s");

  const Stat* accesses = r.stats.find("memory", "accesses");
  for (const Stat& s : r.stats.all()) {
    add(s.location, s.name, s.value, s.unit);
    // What share of the line accesses each level served.
    if (s.name == "served" && accesses)
      add(s.location, "served_share", accesses->value > 0 ? s.value / accesses->value : 0.0, "");
    if (s.name == "capacity") add(s.location, "utilisation", utilisation_of(r, s.location), "");
    if (s.name == "energy_per_lookup" || s.name == "energy_per_bit") add(s.location, "energy", energy_at(r, s.location), "J");
  }
  return out;
}

bool is_stat_row(const Metric& m) {
  if (m.location == "frame" || m.location.rfind("frame[", 0) == 0) return false;
  if (m.metric == "served_share" || m.metric == "utilisation" || m.metric == "energy") return false;
  const bool gpm_itself = m.location.rfind("gpm[", 0) == 0 && m.location.back() == ']' &&
                          m.location.find_first_not_of("0123456789", 4) == m.location.size() - 1;
  return !(gpm_itself && m.metric == "busy");
}

}  // namespace oovr
