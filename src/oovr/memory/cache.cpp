#include "oovr/memory/cache.h"

#include <algorithm>

#include "oovr/core/error.h"
#include "oovr/core/rng.h"

namespace oovr {

Cache::Cache(const CacheSpec& spec, uint64_t line_bytes, std::string name) : m_name(std::move(name)), m_assoc(spec.ways) {
  const uint64_t lines = spec.size.value / line_bytes;
  const uint64_t sets = lines / uint64_t(m_assoc);
  if (sets == 0 || (sets & (sets - 1)) != 0) throw Error("cache " + m_name + ": the number of sets must be a power of two");
  m_set_mask = sets - 1;
  m_tags.assign(lines, kEmpty);
  m_dirty.assign(lines, 0);
  m_category.assign(lines, Category::command);
  m_state.resize(lines);
  m_mru.assign(sets, kEmpty);
  const ReplacementFactory* f = ReplacementPolicies::find(spec.replacement);
  if (!f) throw Error("cache " + m_name + ": unknown replacement policy '" + spec.replacement + "'");
  // Seeded by name: reproducible, different per cache.
  uint64_t seed = 0;
  for (char c : m_name) seed = mix64(seed ^ uint64_t(uint8_t(c)));
  m_policy = f->make(seed);
}

void Cache::insert(uint64_t line, bool write, Category category, Eviction& ev, uint64_t first) {
  int victim = -1;
  for (int i = 0; i < m_assoc; ++i)
    if (m_tags[first + uint64_t(i)] == kEmpty) {
      victim = i;
      break;
    }
  if (victim < 0) {
    victim = m_policy->victim(&m_state[first], m_assoc);
    const uint64_t v = first + uint64_t(victim);
    if (m_dirty[v]) {
      ev.dirty = true;
      ev.line = m_tags[v];
      ev.category = m_category[v];
    }
  }
  const uint64_t v = first + uint64_t(victim);
  m_tags[v] = line;
  m_dirty[v] = write;
  m_category[v] = category;
  m_state[v] = {m_clock, m_clock};
}

bool Cache::contains(uint64_t line) const {
  const uint64_t first = (line & m_set_mask) * uint64_t(m_assoc);
  for (int i = 0; i < m_assoc; ++i)
    if (m_tags[first + uint64_t(i)] == line) return true;
  return false;
}

void Cache::invalidate(uint64_t line) {
  const uint64_t first = (line & m_set_mask) * uint64_t(m_assoc);
  for (int i = 0; i < m_assoc; ++i)
    if (m_tags[first + uint64_t(i)] == line) {
      m_tags[first + uint64_t(i)] = kEmpty;
      m_dirty[first + uint64_t(i)] = 0;
      if (m_mru[line & m_set_mask] == line) m_mru[line & m_set_mask] = kEmpty;
    }
}

uint64_t Cache::invalidate_all() {
  uint64_t dirty = 0;
  for (uint8_t d : m_dirty) dirty += d;
  std::fill(m_tags.begin(), m_tags.end(), kEmpty);
  std::fill(m_dirty.begin(), m_dirty.end(), 0);
  std::fill(m_mru.begin(), m_mru.end(), kEmpty);
  return dirty;
}

}  // namespace oovr
