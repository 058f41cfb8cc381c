// FrameTrace's totals (frame_trace.h), beside the trace they add up.
#include "oovr/pipeline/frame_trace.h"

#include <algorithm>
#include <mutex>
#include <span>

#include "oovr/core/error.h"
#include "oovr/core/hash.h"

namespace oovr {

uint64_t FrameTrace::total_covered() const {
  uint64_t n = 0;
  for (const auto& t : tiles) n += t.covered;
  return n;
}

uint64_t FrameTrace::total_passed() const {
  uint64_t n = 0;
  for (const auto& t : tiles) n += t.passed;
  return n;
}

uint64_t FrameTrace::layer_fetches() const {
  uint64_t n = 0;
  for (const auto& t : tiles) n += uint64_t(t.shaded) * objects[t.object].texture_layers;
  return n;
}

uint64_t FrameTrace::unique_tex_lines() const {
  std::vector<TexLine> lines(tex_lines.begin(), tex_lines.end());
  std::sort(lines.begin(), lines.end());
  return uint64_t(std::unique(lines.begin(), lines.end()) - lines.begin());
}

struct FrameTraceMemo::Impl {
  std::mutex mutex;
  struct Entry {
    uint64_t modulus;
    int lru_ways;
    // What the trace was when this was derived.
    const TileWork* tiles;
    size_t records;
    const TexLine* lines;
    size_t line_count;
    std::shared_ptr<const TexLinesWithoutRepeats> value;  // null: not worth keeping
  };
  std::vector<Entry> without_repeats;
  // records_checksum(), and the records it was computed from.
  const TileWork* summed_tiles = nullptr;
  size_t summed_records = 0;
  uint64_t checksum = 0;
};

FrameTraceMemo::FrameTraceMemo() : m_impl(std::make_unique<Impl>()) {}
FrameTraceMemo::FrameTraceMemo(const FrameTraceMemo&) : m_impl(std::make_unique<Impl>()) {}
FrameTraceMemo& FrameTraceMemo::operator=(const FrameTraceMemo&) {
  std::lock_guard lock(m_impl->mutex);
  m_impl->without_repeats.clear();
  m_impl->summed_tiles = nullptr;
  return *this;
}
FrameTraceMemo::~FrameTraceMemo() = default;

namespace {

// A record's lines less its repeats (tex_lines_without_repeats), with the
// scratch kept from record to record: per index modulo M, a stamp saying
// which record its entries are of, so that nothing is reset between records.
class RepeatFilter {
 public:
  RepeatFilter(uint64_t modulus, int lru_ways)
      : m_mask(modulus - 1),
        m_ways(lru_ways),
        m_last(modulus),
        m_stamp(modulus, 0),
        m_stack(lru_ways > 0 ? modulus * uint64_t(lru_ways) : 0),
        m_depth(lru_ways > 0 ? modulus : 0),
        m_after(lru_ways > 0 ? modulus * uint64_t(lru_ways + 1) : 0),
        m_after_count(lru_ways > 0 ? modulus : 0) {}

  // Appends record `record`'s kept lines (of `lines`) to `out`.
  void filter(uint32_t record, std::span<const TexLine> lines, std::vector<TexLine>& out) {
    const uint32_t stamp = record + 1;
    // Reads of the line the set last read in the record: hits on its most
    // recently used line, which change nothing (with any policy).
    m_kept.clear();
    for (const TexLine l : lines) {
      const uint64_t k = tex_line_index(l) & m_mask;
      if (m_stamp[k] == stamp && m_last[k] == l) continue;
      if (m_stamp[k] != stamp && m_ways > 0) m_depth[k] = m_after_count[k] = 0;  // the set's first read in the record
      m_stamp[k] = stamp;
      m_last[k] = l;
      m_kept.push_back(l);
    }
    if (m_ways == 0) {
      out.insert(out.end(), m_kept.begin(), m_kept.end());
      return;
    }
    // With least-recently-used replacement of W ways: a read of a line the
    // set read in the record with fewer than W other lines of the set since
    // is sure to hit (its stack distance is under W). Such a hit is left
    // out where the record reads the line again with only sure hits of the
    // set between: until then no line of the set is replaced, and at every
    // read that may miss, and at the record's end, each line's last read is
    // kept, so the set's order of last uses, the only thing LRU reads, is
    // the same (Cache::access; replacement/impl/lru.cpp).
    const size_t n = m_kept.size();
    m_sure.assign(n, 0);
    const int ways = m_ways;
    for (size_t i = 0; i < n; ++i) {
      const TexLine l = m_kept[i];
      const uint64_t k = tex_line_index(l) & m_mask;
      TexLine* stack = &m_stack[k * uint64_t(ways)];
      int& depth = m_depth[k];
      // The stack's lines are distinct: the first match is the only one.
      int at = 0;
      while (at < depth && stack[at] != l) ++at;
      if (at == depth) at = -1;
      m_sure[i] = at >= 0;
      if (at < 0) at = depth < ways ? depth++ : ways - 1;
      move_down(stack, at);
      stack[0] = l;
    }
    // Backwards: per set, the lines read after this read with only sure
    // hits of the set before them (at most W + 1: the sure hits' lines are
    // the W in the stack).
    const size_t first = out.size();
    for (size_t i = n; i-- > 0;) {
      const TexLine l = m_kept[i];
      const uint64_t k = tex_line_index(l) & m_mask;
      TexLine* after = &m_after[k * uint64_t(ways + 1)];
      int& count = m_after_count[k];
      if (!m_sure[i]) {
        count = 0;
      } else {
        // The lines after are distinct too.
        int w = 0;
        while (w < count && after[w] != l) ++w;
        if (w < count) continue;  // a sure hit read again before the set may miss
      }
      if (count <= ways) after[count++] = l;
      out.push_back(l);
    }
    std::reverse(out.begin() + std::ptrdiff_t(first), out.end());
  }

 private:
  // Moves stack[0 .. at) one place down. Element by element up to four
  // ways (Table 1's L1): GCC makes the loop a call to memmove, a call per
  // read whose wide stores the next search of the set, often the next
  // read's (a material's layers alternate in one set), likely waits on;
  // written out, nexuiz:strength's list takes 12% fewer instructions
  // (docs/performance.md, "The repeat filter's moves written out").
  static void move_down(TexLine* stack, int at) {
    switch (at) {
      case 0: return;
      case 3: stack[3] = stack[2]; [[fallthrough]];
      case 2: stack[2] = stack[1]; [[fallthrough]];
      case 1: stack[1] = stack[0]; return;
      default:
        for (int w = at; w > 0; --w) stack[w] = stack[w - 1];
    }
  }

  uint64_t m_mask;
  int m_ways;
  std::vector<TexLine> m_last;
  std::vector<uint32_t> m_stamp;
  std::vector<TexLine> m_stack;  // per set, the record's last W distinct lines, most recent first
  std::vector<int> m_depth;
  std::vector<TexLine> m_after;
  std::vector<int> m_after_count;
  std::vector<TexLine> m_kept;
  std::vector<uint8_t> m_sure;
};

}  // namespace

bool FrameTrace::repeats_derivable(uint64_t modulus, int lru_ways) {
  // The LRU rule's scratch is a stack of W lines and a list of W + 1 per
  // set: bounded (2^24 lines each, 128 MB).
  return modulus != 0 && (modulus & (modulus - 1)) == 0 && modulus <= (uint64_t(1) << 20) && lru_ways >= 0 && lru_ways <= 1024 &&
         modulus * uint64_t(lru_ways + 1) <= (uint64_t(1) << 24);
}

std::shared_ptr<const TexLinesWithoutRepeats> FrameTrace::tex_lines_without_repeats(uint64_t modulus, int lru_ways) const {
  if (!repeats_derivable(modulus, 0))
    throw Error("tex_lines_without_repeats: the modulus must be a power of two up to 2^20, not " + std::to_string(modulus));
  if (!repeats_derivable(modulus, lru_ways))
    throw Error(
        "tex_lines_without_repeats: an LRU cache here has 1 to 1024 ways and at most 2^24 lines (0 ways: any "
        "policy), not " +
        std::to_string(lru_ways) + " ways of " + std::to_string(modulus) + " sets");
  FrameTraceMemo::Impl& m = *memo.m_impl;
  // One thread derives; the others replaying the frame wait for it rather
  // than derive it again.
  std::lock_guard lock(m.mutex);
  for (const auto& e : m.without_repeats)
    if (e.modulus == modulus && e.lru_ways == lru_ways && e.tiles == tiles.data() && e.records == tiles.size() &&
        e.lines == tex_lines.data() && e.line_count == tex_lines.size())
      return e.value;
  std::erase_if(m.without_repeats, [&](const auto& e) { return e.modulus == modulus && e.lru_ways == lru_ways; });
  std::shared_ptr<TexLinesWithoutRepeats> out;
  if (tiles.size() < UINT32_MAX) {
    out = std::make_shared<TexLinesWithoutRepeats>();
    out->modulus = modulus;
    out->lru_ways = lru_ways;
    out->begin.reserve(tiles.size() + 1);
    RepeatFilter filter(modulus, lru_ways);
    const uint64_t half = tex_lines.size() / 2;
    for (size_t r = 0; r < tiles.size() && out; ++r) {
      out->begin.push_back(out->lines.size());
      const TileWork& t = tiles[r];
      filter.filter(uint32_t(r), {tex_lines.data() + t.tex_begin, t.tex_count}, out->lines);
      if (out->lines.size() > half) out.reset();  // no shorter to replay than the whole
    }
    if (out && out->lines.size() * 2 < tex_lines.size()) {
      out->begin.push_back(out->lines.size());
      out->lines.shrink_to_fit();
    } else {
      out.reset();
    }
  }
  m.without_repeats.push_back({modulus, lru_ways, tiles.data(), tiles.size(), tex_lines.data(), tex_lines.size(), out});
  return out;
}

uint64_t FrameTrace::records_checksum() const {
  // Every run that records or plays a memory tape sums its frames' records
  // (schemes/frame_sim.cpp): once per frame, not per run and pass.
  FrameTraceMemo::Impl& m = *memo.m_impl;
  std::lock_guard lock(m.mutex);
  if (m.summed_tiles != tiles.data() || m.summed_records != tiles.size() || !m.summed_tiles) {
    m.checksum = checksum64({reinterpret_cast<const char*>(tiles.data()), tiles.size() * sizeof(TileWork)});
    m.summed_tiles = tiles.data();
    m.summed_records = tiles.size();
  }
  return m.checksum;
}

}  // namespace oovr
