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

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
  //
  // The paper's L1 (4 ways) and L2s (16) with LRU are inlined into the
  // memory system's loop with their ways known; a call per line, its
  // register saves and the dispatch on the shape cost 8% of a replay's
  // instructions. Any other shape is served out of line (access_other()).
  [[gnu::always_inline]] bool access(uint64_t line, bool write, Category category, Eviction& ev) {
    if (m_shape == Shape::lru4) return access_ordered<4>(line, write, category, ev);
    if (m_shape == Shape::lru16) return access_ordered<16>(line, write, category, ev);
    return access_other(line, write, category, ev);
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
  // A hit moves the entries in front of it: by memmove, which measured
  // fewer instructions and mispredicted branches than selects over a copy
  // of the set (2.5% of a replay's instructions for the paper's 16-way
  // L2s) or a loop carrying each entry in a register. A miss moves every
  // entry, in whole vectors (shift_all()).
  static void move_on(uint64_t* e, int n) { std::memmove(e + 1, e, sizeof(uint64_t) * size_t(n)); }
  // W: the ways, when known (else 0: m_assoc).
  template <int W>
  [[gnu::always_inline]] bool access_ordered(uint64_t line, bool write, Category category, Eviction& ev) {
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
    if (const int i = find_after_first<W>(e, ways, tag)) {
      const uint64_t hit = e[i] | dirty;
      if constexpr (W == 4) {
        // Four ways: the entries in front of the hit moved on by selects
        // (a call to memmove of 8 to 24 bytes cost more).
        const uint64_t e0 = e[0], e1 = e[1], e2 = e[2], e3 = e[3];
        e[1] = e0;
        e[2] = i >= 2 ? e1 : e2;
        e[3] = i >= 3 ? e2 : e3;
      } else {
        move_on(e, i);
      }
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
    shift_all<W>(e, ways);
    e[0] = tag | dirty | uint64_t(uint8_t(category)) << 40;
    return false;
  }
  // A miss's move: every entry one way on (move_on(e, ways - 1)), for the
  // paper's shapes in whole vectors (selects over a copy of the set spent
  // 2.5% of a replay's instructions on the misses of its 16-way L2s).
  template <int W>
  [[gnu::always_inline]] static void shift_all(uint64_t* e, int ways) {
#if defined(__SSE2__)
    if constexpr (W == 4 || W == 16) {
      // Every load before the first store; the last entry moved on is
      // loaded alone (W - 1 is odd).
      __m128i v[W / 2 - 1];
      for (int k = 0; k < W / 2 - 1; ++k) v[k] = _mm_load_si128(reinterpret_cast<const __m128i*>(e + 2 * k));
      const uint64_t last = e[W - 2];
      for (int k = 0; k < W / 2 - 1; ++k) _mm_storeu_si128(reinterpret_cast<__m128i*>(e + 1 + 2 * k), v[k]);
      e[W - 1] = last;
      return;
    }
#endif
    move_on(e, ways - 1);
  }
#if defined(__SSE2__)
  // Entries k to k + 3 whose tag (low 32 bits) is `t`'s lanes, as four
  // all-ones or zero lanes in order: two 16-byte-aligned loads, a shuffle
  // taking each entry's low word, a compare.
  [[gnu::always_inline]] static __m128i tags_equal4(const uint64_t* e, int k, __m128i t) {
    const __m128 a = _mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(e + k)));
    const __m128 b = _mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(e + k + 2)));
    return _mm_cmpeq_epi32(_mm_castps_si128(_mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))), t);
  }
#endif
  // The first of a set's ways 1 to `ways` - 1 whose entry holds `tag`
  // (below kEmpty), or 0 when none does. A miss in a 16-way
  // set compared every way one by one, 6% of a replay's instructions; with
  // SSE2 four ways' tags (each entry's low 32 bits) are compared at once.
  template <int W>
  [[gnu::always_inline]] static int find_after_first(const uint64_t* e, int ways, uint64_t tag) {
#if defined(__SSE2__)
    const __m128i t = _mm_set1_epi32(int(uint32_t(tag)));
    if constexpr (W == 4 || W == 16) {
      // The blocks start at a 64-byte boundary and are 32 or 128 bytes
      // (block_bytes()), so every load is 16-byte aligned.
      __m128i eq[W / 4];
      for (int k = 0; k < W / 4; ++k) eq[k] = tags_equal4(e, 4 * k, t);
      unsigned mask;
      if constexpr (W == 4) {
        mask = unsigned(_mm_movemask_ps(_mm_castsi128_ps(eq[0])));
      } else {
        // Saturating packs keep each all-ones or zero lane's sign: one
        // byte per way, in order.
        const __m128i lo = _mm_packs_epi32(eq[0], eq[1]), hi = _mm_packs_epi32(eq[2], eq[3]);
        mask = unsigned(_mm_movemask_epi8(_mm_packs_epi16(lo, hi)));
      }
      mask &= ~1u;
      return mask ? std::countr_zero(mask) : 0;
    }
    // Any other multiple of four ways (ideal's 64-way L2, a study's 8 or
    // 32), four at a time, the first match in order: a block of 4k ways is
    // 32 bytes or a multiple of 64, so every load is 16-byte aligned.
    if (ways % 4 == 0) {
      for (int k = 0; k < ways; k += 4) {
        unsigned mask = unsigned(_mm_movemask_ps(_mm_castsi128_ps(tags_equal4(e, k, t))));
        if (k == 0) mask &= ~1u;
        if (mask) return k + std::countr_zero(mask);
      }
      return 0;
    }
#endif
    for (int i = 1; i < ways; ++i)
      if (entry_tag(e[i]) == tag) return i;
    return 0;
  }
  [[noreturn]] void refuse(uint64_t line) const;
  // access() for every shape but lru4 and lru16.
  [[gnu::noinline]] bool access_other(uint64_t line, bool write, Category category, Eviction& ev);

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
  // The shapes access() inlines (recency-ordered sets of 4 and 16 ways).
  enum class Shape : uint8_t { lru4, lru16, other } m_shape = Shape::other;
  int m_assoc;
  uint64_t m_sets, m_set_mask, m_block_bytes;
  int m_tag_shift;
  std::unique_ptr<uint8_t[], Free> m_blocks;
  std::unique_ptr<ReplacementPolicy> m_policy;
  uint32_t m_clock = 0;
};

}  // namespace oovr
