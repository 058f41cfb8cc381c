#include "oovr/core/stats.h"

#include <cmath>
#include <map>
#include <utility>

#include "oovr/core/error.h"

namespace oovr {

const char* merge_name(Merge m) {
  switch (m) {
    case Merge::sum: return "sum";
    case Merge::mean: return "mean";
    case Merge::max: return "max";
  }
  return "?";
}

namespace {

std::string where(const std::string& location, const std::string& name) { return "statistic '" + location + " " + name + "'"; }

}  // namespace

void Stats::add(std::string location, std::string name, double value, std::string unit, Merge merge) {
  if (!std::isfinite(value)) throw Error(where(location, name) + " is not a finite number");
  if (find(location, name)) throw Error(where(location, name) + " is registered twice");
  m_stats.push_back({std::move(location), std::move(name), std::move(unit), merge, false, value});
}

void Stats::count(std::string location, std::string name, uint64_t value, std::string unit) {
  if (value >= (uint64_t(1) << 53)) throw Error(where(location, name) + " counts past 2^53, more than a double holds exactly");
  add(std::move(location), std::move(name), double(value), std::move(unit), Merge::sum);
  m_stats.back().whole = true;
}

void Stats::append(const Stats& other) {
  for (const Stat& s : other.m_stats) {
    if (find(s.location, s.name)) throw Error(where(s.location, s.name) + " is registered twice");
    m_stats.push_back(s);
  }
}

const Stat* Stats::find(const std::string& location, const std::string& name) const {
  for (const Stat& s : m_stats)
    if (s.name == name && s.location == location) return &s;
  return nullptr;
}

double Stats::at(const std::string& location, const std::string& name) const {
  const Stat* s = find(location, name);
  if (!s) throw Error(where(location, name) + " was not reported");
  return s->value;
}

Stats Stats::since(const Stats& before) const {
  if (before.m_stats.size() != m_stats.size()) throw Error("statistics: two snapshots of different owners");
  Stats d = *this;
  for (size_t i = 0; i < m_stats.size(); ++i) {
    const Stat& b = before.m_stats[i];
    Stat& s = d.m_stats[i];
    if (b.location != s.location || b.name != s.name) throw Error("statistics: two snapshots of different owners");
    if (s.merge == Merge::sum) s.value -= b.value;
  }
  return d;
}

Stats Stats::window(const std::vector<const Stats*>& runs, uint64_t frames) {
  Stats w;
  std::map<std::pair<std::string, std::string>, std::pair<size_t, uint64_t>> seen;  // -> (index in w, runs reporting it)
  for (const Stats* r : runs)
    for (const Stat& s : r->m_stats) {
      auto [it, first] = seen.try_emplace({s.location, s.name}, w.m_stats.size(), 0);
      ++it->second.second;
      if (first) {
        w.m_stats.push_back(s);
        continue;
      }
      Stat& x = w.m_stats[it->second.first];
      if (x.merge != s.merge || x.whole != s.whole || x.unit != s.unit)
        throw Error(where(s.location, s.name) + " is reported with different rules by the runs of a window");
      if (s.merge == Merge::max) x.value = std::max(x.value, s.value);
      else x.value += s.value;
    }
  for (const auto& [key, at] : seen) {
    Stat& x = w.m_stats[at.first];
    if (x.merge == Merge::mean) {
      x.value /= double(at.second);
    } else if (x.merge == Merge::sum && frames > 1) {
      if (x.whole) {
        const uint64_t v = uint64_t(x.value);
        x.value = double((v + frames / 2) / frames);  // to nearest, as integer counts divide
      } else {
        x.value /= double(frames);
      }
    }
  }
  return w;
}

}  // namespace oovr
