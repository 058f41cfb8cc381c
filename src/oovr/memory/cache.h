// A set-associative cache of lines, write-back, write-allocate, with a
// pluggable replacement policy. Tags only: the simulator needs hits, misses
// and evictions, not data.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "oovr/memory/category.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/memory/replacement/i_replacement.h"

namespace oovr {

class Cache {
 public:
  // What one line's tag and state take (tag, dirty bit, category, the
  // replacement policy's state), for memory estimates.
  static constexpr uint64_t kBytesPerLine = sizeof(uint64_t) + sizeof(uint8_t) + sizeof(Category) + sizeof(WayState);
  Cache(const CacheSpec& spec, uint64_t line_bytes, std::string name);

  struct Eviction {
    bool dirty = false;
    uint64_t line = 0;
    Category category = Category::command;
  };

  // Looks `line` up; a hit refreshes it and returns true. A miss inserts it,
  // evicting a victim when the set is full (reported in `ev` when dirty),
  // and returns false. Writes mark the line dirty.
  bool access(uint64_t line, bool write, Category category, Eviction& ev) {
    const uint64_t set = line & m_set_mask, first = set * uint64_t(m_assoc);
    // A read of the set's most recently used line hits and changes no
    // set's order, so nothing else is done (replacement policies read only
    // the order of the counters: replacement/i_replacement.h). Texture
    // lines repeat from quad to quad, so this is most of an L1's reads.
    if (m_mru[set] == line && !write) return true;
    const uint64_t* tags = &m_tags[first];
    ++m_clock;
    // Scan every way without an early exit: no hard-to-predict branch per
    // way, and sets are short (at most 1024 ways, usually 4 to 16).
    int hit = -1;
    for (int i = 0; i < m_assoc; ++i) hit = tags[i] == line ? i : hit;
    if (hit >= 0) {
      m_state[first + uint64_t(hit)].last_use = m_clock;
      m_mru[set] = line;
      if (write) m_dirty[first + uint64_t(hit)] = 1;
      return true;
    }
    insert(line, write, category, ev, first);
    m_mru[set] = line;
    return false;
  }
  // True when the line is cached; changes nothing.
  bool contains(uint64_t line) const;
  // Drops the line if cached (no write-back: used for write-through copies).
  void invalidate(uint64_t line);
  // Drops everything; returns the dirty lines dropped.
  uint64_t invalidate_all();

  const std::string& name() const { return m_name; }
  uint64_t lines() const { return m_tags.size(); }
  uint64_t set_mask() const { return m_set_mask; }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  void insert(uint64_t line, bool write, Category category, Eviction& ev, uint64_t first);

  std::string m_name;
  int m_assoc;
  uint64_t m_set_mask;
  // Per way, set by set: tags apart from the rest so that a lookup scans
  // one contiguous run of tags.
  std::vector<uint64_t> m_tags;
  std::vector<uint8_t> m_dirty;
  std::vector<Category> m_category;
  std::vector<WayState> m_state;
  std::vector<uint64_t> m_mru;  // per set: its most recently used line (kEmpty: not known)
  std::unique_ptr<ReplacementPolicy> m_policy;
  uint64_t m_clock = 0;
};

}  // namespace oovr
