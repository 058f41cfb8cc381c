// A set-associative cache of lines, write-back, write-allocate, with a
// pluggable replacement policy. Tags only: the simulator needs hits, misses
// and evictions, not data.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <string>

#include "oovr/memory/category.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/memory/replacement/i_replacement.h"

namespace oovr {

class Cache {
 public:
  // The bytes a cache of this shape keeps (its sets' blocks, below), for
  // memory estimates: with LRU 8 a line where a set's 8 bytes a way fill a
  // block (1, 2, 4 or 8 ways, or a multiple of 8), up to 15 at other ways;
  // with another policy 16 a line from 4 ways up, 32 at 2 ways, 64 at 1.
  static uint64_t state_bytes(const CacheSpec& spec, uint64_t line_bytes);
  Cache(const CacheSpec& spec, uint64_t line_bytes, std::string name);
  Cache(Cache&&) noexcept = default;
  Cache& operator=(Cache&&) noexcept = default;

  struct Eviction {
    bool dirty = false;
    uint64_t line = 0;
    Category category = Category::command;
  };

  // Looks `line` up; a hit refreshes it and returns true. A miss inserts it,
  // evicting a victim when the set is full (reported in `ev` when dirty),
  // and returns false. Writes mark the line dirty.
  bool access(uint64_t line, bool write, Category category, Eviction& ev) {
    if (m_ordered) {
      // The paper's L1 (4 ways) and L2s (16) with their ways known.
      if (m_assoc == 4) return access_ordered<4>(line, write, category, ev);
      if (m_assoc == 16) return access_ordered<16>(line, write, category, ev);
      return access_ordered<0>(line, write, category, ev);
    }
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
  // True when the line is cached; changes nothing.
  bool contains(uint64_t line) const;
  // Drops the line if cached (no write-back: used for write-through copies).
  void invalidate(uint64_t line);
  // Drops everything; returns the dirty lines dropped.
  uint64_t invalidate_all();

  const std::string& name() const { return m_name; }
  uint64_t lines() const { return m_sets * uint64_t(m_assoc); }
  uint64_t set_mask() const { return m_set_mask; }
  // Whether every line up to `line` has a tag (32 bits of its line number
  // above the set's bits): up to 2^47 bytes for the paper's L1 (256 sets
  // of 128-byte lines), 2^48 for its L2s. The memory system checks its
  // address map against it.
  bool holds(uint64_t line) const { return (line >> m_tag_shift) < kEmpty; }
  // Moves the access counter on, as if accesses had been made to no set,
  // to `left` (at least 1) accesses before it must be renumbered (through a
  // renumbering, if it is nearer than that): lets tests reach renumber()
  // without four billion accesses.
  void skip_clock_to(uint32_t left);

 private:
  static constexpr uint32_t kEmpty = ~uint32_t(0);
  // A set's bytes in either layout (below): a multiple of 64, or a power of
  // two below it for a recency-ordered set of up to 8 ways, so that no set
  // of 64 bytes or less straddles two of the host's cache lines.
  static constexpr uint64_t block_bytes(uint64_t ways, bool ordered) {
    return ordered && ways <= 8 ? std::bit_ceil(8 * ways) : ((ordered ? 8 * ways : 8 + 14 * ways) + 63) / 64 * 64;
  }

  // Recency-ordered sets, for a policy that evicts the least recently used
  // way (ReplacementFactory::least_recently_used): the order of use is all
  // it reads, so a set keeps its ways' entries in that order, the most
  // recently used first and the ways that hold no line last. An entry is 8
  // bytes: the tag in the low 32 bits (kEmpty: no line), the dirty bit at
  // bit 32, the category in bits 40 to 47. A hit moves its entry to the
  // front, a miss drops the last and puts the new line first: no counter is
  // kept and no victim searched for, and a set of the paper's L1 (4 ways)
  // is 32 bytes, of its L2 (16 ways) 128, where the other layout takes 64
  // and 256.
  static constexpr uint64_t kDirtyBit = uint64_t(1) << 32;
  static uint64_t entry_tag(uint64_t e) { return e & kEmpty; }
  uint64_t* entries_of(uint64_t line) const { return reinterpret_cast<uint64_t*>(block_of(line)); }
  // Moves a set's first `n` entries one way on (the first is then free).
  // With the ways known, as selects over a copy of the set, which the
  // compiler keeps in registers; a call to memmove took 6% of a replay.
  template <int W>
  void move_on(uint64_t* e, int n) const {
    if constexpr (W > 0) {
      uint64_t old[W];
      std::memcpy(old, e, sizeof old);
      for (int j = 1; j < W; ++j) e[j] = j <= n ? old[j - 1] : old[j];
    } else {
      std::memmove(e + 1, e, sizeof(uint64_t) * size_t(n));
    }
  }
  // W: the ways, when known (else 0: m_assoc).
  template <int W>
  bool access_ordered(uint64_t line, bool write, Category category, Eviction& ev) {
    const int ways = W > 0 ? W : m_assoc;
    uint64_t* e = entries_of(line);
    const uint64_t tag = line >> m_tag_shift;
    // A line too far for a tag would match the ways that hold none.
    if (tag >= kEmpty) [[unlikely]]
      refuse(line);
    const uint64_t dirty = write ? kDirtyBit : 0;
    // The most recently used line (as the other layout's shortcut; a write
    // marks it dirty): no order changes.
    if (entry_tag(e[0]) == tag) {
      e[0] |= dirty;
      return true;
    }
    for (int i = 1; i < ways; ++i)
      if (entry_tag(e[i]) == tag) {
        const uint64_t hit = e[i] | dirty;
        move_on<W>(e, i);
        e[0] = hit;
        return true;
      }
    // A miss: the last way is the least recently used line, or holds none
    // (then no line is evicted, as the other layout fills an empty way).
    const uint64_t last = e[ways - 1];
    if (entry_tag(last) != kEmpty && (last & kDirtyBit)) {
      ev.dirty = true;
      ev.line = entry_tag(last) << m_tag_shift | (line & m_set_mask);
      ev.category = Category(uint8_t(last >> 40));
    }
    move_on<W>(e, ways - 1);
    e[0] = tag | dirty | uint64_t(uint8_t(category)) << 40;
    return false;
  }
  [[noreturn]] void refuse(uint64_t line) const;

  // The other policies' sets (FIFO, random, any registered later), with
  // the counters the policy reads. Each set is one block of m_block_bytes,
  // so that a lookup and a replacement touch one set's bytes and no others:
  // its most recently used line (8 bytes; ~0: not known), then per way its
  // tag, the counter at its last use, the counter at its insertion (4 bytes
  // each), its dirty bit and its category (a byte each). A set of 4 ways is
  // 64 bytes, of 16 ways 256.
  static constexpr uint64_t kNoLine = ~uint64_t(0);  // a block's most recently used line when none is known
  // The block of the set `line` falls in (a set index below the sets names its own).
  uint8_t* block_of(uint64_t line) const { return m_blocks.get() + (line & m_set_mask) * m_block_bytes; }
  static uint64_t mru(const uint8_t* b) { return *reinterpret_cast<const uint64_t*>(b); }
  static void set_mru(uint8_t* b, uint64_t line) { *reinterpret_cast<uint64_t*>(b) = line; }
  uint32_t* tags_of(uint8_t* b) const { return reinterpret_cast<uint32_t*>(b + 8); }
  const uint32_t* tags_of(const uint8_t* b) const { return reinterpret_cast<const uint32_t*>(b + 8); }
  uint32_t* last_use_of(uint8_t* b) const { return tags_of(b) + m_assoc; }
  uint32_t* inserted_of(uint8_t* b) const { return tags_of(b) + 2 * m_assoc; }
  uint8_t* dirty_of(uint8_t* b) const { return b + 8 + 12 * uint64_t(m_assoc); }
  Category* category_of(uint8_t* b) const { return reinterpret_cast<Category*>(b + 8 + 13 * uint64_t(m_assoc)); }

  // The access counter, 32 bits: at its last value every set's counters are
  // renumbered first.
  void tick() {
    if (++m_clock == kEmpty) [[unlikely]]
      renumber();
  }
  void renumber();
  // Leaves a set's block holding no line (its ways' counters and categories
  // as they were: they are read only beside a tag).
  void empty_set(uint8_t* block);
  void insert(uint8_t* block, uint64_t line, bool write, Category category, Eviction& ev);

  struct Free {
    void operator()(uint8_t* p) const { ::operator delete[](p, std::align_val_t(64)); }
  };

  std::string m_name;
  bool m_ordered = false;  // recency-ordered sets (LRU), else counters
  int m_assoc;
  uint64_t m_sets, m_set_mask, m_block_bytes;
  int m_tag_shift;
  std::unique_ptr<uint8_t[], Free> m_blocks;
  std::unique_ptr<ReplacementPolicy> m_policy;
  uint32_t m_clock = 0;
};

}  // namespace oovr
