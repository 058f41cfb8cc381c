#include "oovr/experiments/result_metrics.h"

#include "oovr/memory/category.h"

namespace oovr {

namespace {

std::string gpm(size_t g) { return "gpm[" + std::to_string(g) + "]"; }

// The topology's name for a link ("gpm0->gpm1", "gpm2->switch0") ->
// "link[0->1]", "link[2->switch0]".
std::string link_location(const std::string& name, size_t index) {
  const auto arrow = name.find("->");
  if (arrow == std::string::npos) return "link[" + std::to_string(index) + "]";
  const auto node = [](std::string n) { return n.rfind("gpm", 0) == 0 ? n.substr(3) : n; };
  return "link[" + node(name.substr(0, arrow)) + "->" + node(name.substr(arrow + 2)) + "]";
}

}  // namespace

std::vector<Metric> metrics_of(const SchemeResult& r) {
  std::vector<Metric> out;
  const auto add = [&](const std::string& location, const std::string& metric, double value, const char* unit) {
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
  for (size_t k = 0; k < r.frame_latencies_s.size(); ++k)
    add("frame[" + std::to_string(k) + "]", "latency", r.frame_latencies_s[k], "s");
  for (size_t g = 0; g < r.gpm_busy_s.size(); ++g) add(gpm(g), "busy", r.gpm_busy_s[g], "s");

  // The memory system: what share of the line accesses each level served.
  const MemoryStats& m = r.memory;
  add("memory", "accesses", double(m.accesses), "");
  const struct {
    const char* level;
    uint64_t served;
  } levels[] = {
      {"l1", m.l1_hits}, {"l2", m.l2_hits}, {"remote_cache", m.remote_hits}, {"home_l2", m.home_l2_hits}, {"dram", m.dram_lines}};
  for (const auto& l : levels) {
    add(l.level, "served", double(l.served), "");
    add(l.level, "served_share", m.accesses ? double(l.served) / double(m.accesses) : 0.0, "");
  }
  for (size_t g = 0; g < m.dram_bytes.size(); ++g) add(gpm(g) + ".dram", "bytes", double(m.dram_bytes[g]), "B");
  const auto bw = r.config.find("link.bandwidth");
  const double link_bandwidth = bw != r.config.end() && bw->second.base ? *bw->second.base : 0;
  for (size_t l = 0; l < m.link_bytes.size(); ++l) {
    const std::string where = link_location(l < m.link_names.size() ? m.link_names[l] : "", l);
    add(where, "bytes", double(m.link_bytes[l]), "B");
    add(where, "utilisation", link_bandwidth > 0 ? double(m.link_bytes[l]) * r.throughput_fps / link_bandwidth : 0.0, "");
  }
  const size_t n = size_t(r.gpms);
  for (size_t from = 0; from < n && (from + 1) * n <= m.gpm_to_gpm_bytes.size(); ++from)
    for (size_t to = 0; to < n; ++to)
      if (from != to) add(gpm(from) + "->" + gpm(to), "bytes", double(m.gpm_to_gpm_bytes[from * n + to]), "B");

  for (const SchemeMetric& s : r.metrics) out.push_back({r.scheme, s.name, s.value, s.unit});
  return out;
}

}  // namespace oovr
