#include "oovr/memory/cache.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "oovr/core/error.h"
#include "oovr/core/rng.h"

namespace oovr {

uint64_t Cache::state_bytes(const CacheSpec& spec, uint64_t line_bytes) {
  const uint64_t ways = uint64_t(std::max(spec.ways, 1));
  const ReplacementFactory* f = ReplacementPolicies::find(spec.replacement);
  return spec.size.value / std::max<uint64_t>(line_bytes, 1) / ways * block_bytes(ways, f && f->least_recently_used);
}

Cache::Cache(const CacheSpec& spec, uint64_t line_bytes, std::string name) : m_name(std::move(name)), m_assoc(spec.ways) {
  const ReplacementFactory* f = ReplacementPolicies::find(spec.replacement);
  if (!f) throw Error("cache " + m_name + ": unknown replacement policy '" + spec.replacement + "'");
  m_ordered = f->least_recently_used;
  if (m_ordered && m_assoc == 4) m_shape = Shape::lru4;
  if (m_ordered && m_assoc == 16) m_shape = Shape::lru16;
  const uint64_t lines = spec.size.value / line_bytes;
  m_sets = lines / uint64_t(m_assoc);
  if (m_sets == 0 || (m_sets & (m_sets - 1)) != 0) throw Error("cache " + m_name + ": the number of sets must be a power of two");
  m_set_mask = m_sets - 1;
  m_tag_shift = __builtin_ctzll(m_sets);
  m_block_bytes = block_bytes(uint64_t(m_assoc), m_ordered);
  m_blocks.reset(static_cast<uint8_t*>(::operator new[](m_sets* m_block_bytes, std::align_val_t(64))));
  std::memset(m_blocks.get(), 0, m_sets * m_block_bytes);
  for (uint64_t s = 0; s < m_sets; ++s) {
    uint8_t* b = block_of(s);
    empty_set(b);
    if (!m_ordered) std::fill(category_of(b), category_of(b) + m_assoc, Category::command);
  }
  if (m_ordered) return;  // the order is the policy: victim() is never asked
  // Seeded by name: reproducible, different per cache.
  uint64_t seed = 0;
  for (char c : m_name) seed = mix64(seed ^ uint64_t(uint8_t(c)));
  m_policy = f->make(seed);
}

bool Cache::access_other(uint64_t line, bool write, Category category, Eviction& ev) {
  if (m_ordered) return access_ordered<0>(line, write, category, ev);
  uint8_t* block = block_of(line);
  // A read of the set's most recently used line hits and changes no
  // set's order, so nothing else is done (replacement policies read only
  // the order of the counters: replacement/i_replacement.h). Texture
  // lines repeat from quad to quad, so this is most of an L1's reads.
  if (mru(block) == line && !write) return true;
  const uint32_t* tags = tags_of(block);
  // Tags are 32 bits wide; the line's is compared at 64, so a line too
  // far for one (refused by insert()) matches none.
  const uint64_t tag = line >> m_tag_shift;
  tick();
  // Scan every way without an early exit: no hard-to-predict branch per
  // way, and sets are short (at most 1024 ways, usually 4 to 16).
  int hit = -1;
  for (int i = 0; i < m_assoc; ++i) hit = uint64_t(tags[i]) == tag ? i : hit;
  if (hit >= 0) {
    last_use_of(block)[hit] = m_clock;
    set_mru(block, line);
    if (write) dirty_of(block)[hit] = 1;
    return true;
  }
  insert(block, line, write, category, ev);
  set_mru(block, line);
  return false;
}

void Cache::refuse(uint64_t line) const {
  throw Error("cache " + m_name + ": line " + std::to_string(line) + " is past the lines its 32-bit tags can name");
}

void Cache::insert(uint8_t* block, uint64_t line, bool write, Category category, Eviction& ev) {
  const uint64_t tag = line >> m_tag_shift;
  if (tag >= kEmpty) [[unlikely]]
    refuse(line);
  uint32_t* tags = tags_of(block);
  int victim = -1;
  for (int i = 0; i < m_assoc; ++i)
    if (tags[i] == kEmpty) {
      victim = i;
      break;
    }
  if (victim < 0) {
    victim = m_policy->victim({last_use_of(block), inserted_of(block), m_assoc});
    if (dirty_of(block)[victim]) {
      ev.dirty = true;
      ev.line = uint64_t(tags[victim]) << m_tag_shift | (line & m_set_mask);
      ev.category = category_of(block)[victim];
    }
  }
  tags[victim] = uint32_t(tag);
  dirty_of(block)[victim] = write;
  category_of(block)[victim] = category;
  last_use_of(block)[victim] = inserted_of(block)[victim] = m_clock;
}

void Cache::empty_set(uint8_t* block) {
  if (m_ordered) {
    std::fill_n(reinterpret_cast<uint64_t*>(block), m_assoc, uint64_t(kEmpty));
    return;
  }
  std::fill(tags_of(block), tags_of(block) + m_assoc, kEmpty);
  std::fill(dirty_of(block), dirty_of(block) + m_assoc, uint8_t(0));
  set_mru(block, kNoLine);
}

void Cache::renumber() {
  // Each set's counters (last uses and insertions together) replaced by
  // their ranks among the set's: every order a policy may read is kept, and
  // every rank is below 2 x ways, where the clock goes on from.
  std::vector<uint32_t> values;
  for (uint64_t s = 0; s < m_sets; ++s) {
    uint8_t* b = block_of(s);
    uint32_t *use = last_use_of(b), *in = inserted_of(b);
    values.assign(use, use + m_assoc);
    values.insert(values.end(), in, in + m_assoc);
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    const auto rank = [&](uint32_t v) { return uint32_t(std::lower_bound(values.begin(), values.end(), v) - values.begin()); };
    for (int i = 0; i < m_assoc; ++i) {
      use[i] = rank(use[i]);
      in[i] = rank(in[i]);
    }
  }
  m_clock = uint32_t(2 * m_assoc);
}

void Cache::skip_clock_to(uint32_t left) {
  if (m_ordered) return;  // no counters to renumber
  const uint32_t target = kEmpty - std::max<uint32_t>(left, 1);
  if (m_clock > target) {
    m_clock = kEmpty - 1;
    tick();
  }
  m_clock = std::max(m_clock, target);
}

bool Cache::contains(uint64_t line) const {
  if (m_ordered) {
    const uint64_t* e = entries_of(line);
    const uint64_t tag = line >> m_tag_shift;
    for (int i = 0; i < m_assoc; ++i)
      if (entry_tag(e[i]) == tag) return tag != kEmpty;
    return false;
  }
  const uint8_t* b = block_of(line);
  const uint32_t* tags = tags_of(b);
  const uint64_t tag = line >> m_tag_shift;
  for (int i = 0; i < m_assoc; ++i)
    if (uint64_t(tags[i]) == tag) return true;
  return false;
}

void Cache::invalidate(uint64_t line) {
  if (m_ordered) {
    // The others keep their order; the way freed goes last.
    uint64_t* e = entries_of(line);
    const uint64_t tag = line >> m_tag_shift;
    if (tag >= kEmpty) return;
    // The way holding the line, by access()'s search (for the paper's
    // shapes four tags at a time: a write through to another GPM's memory
    // invalidates its line in the remote cache, which most often holds none).
    int i = 0;
    if (entry_tag(e[0]) != tag) {
      i = m_shape == Shape::lru4    ? find_after_first<4>(e, 4, tag)
          : m_shape == Shape::lru16 ? find_after_first<16>(e, 16, tag)
                                    : find_after_first<0>(e, m_assoc, tag);
      if (i == 0) return;
    }
    std::copy(e + i + 1, e + m_assoc, e + i);
    e[m_assoc - 1] = kEmpty;
    return;
  }
  uint8_t* b = block_of(line);
  uint32_t* tags = tags_of(b);
  const uint64_t tag = line >> m_tag_shift;
  for (int i = 0; i < m_assoc; ++i)
    if (uint64_t(tags[i]) == tag) {
      tags[i] = kEmpty;
      dirty_of(b)[i] = 0;
      if (mru(b) == line) set_mru(b, kNoLine);
    }
}

uint64_t Cache::invalidate_all() {
  uint64_t dirty = 0;
  for (uint64_t s = 0; s < m_sets; ++s) {
    uint8_t* b = block_of(s);
    if (m_ordered) {
      const uint64_t* e = reinterpret_cast<const uint64_t*>(b);
      for (int i = 0; i < m_assoc; ++i) dirty += entry_tag(e[i]) != kEmpty && (e[i] & kDirtyBit);
    } else {
      for (int i = 0; i < m_assoc; ++i) dirty += dirty_of(b)[i];
    }
    empty_set(b);
  }
  return dirty;
}

}  // namespace oovr
