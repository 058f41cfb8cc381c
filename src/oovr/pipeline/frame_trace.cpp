// FrameTrace's totals (frame_trace.h), beside the trace they add up.
#include "oovr/pipeline/frame_trace.h"

#include <algorithm>
#include <mutex>

#include "oovr/core/error.h"

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
    // What the trace was when this was derived.
    const TileWork* tiles;
    size_t records;
    const TexLine* lines;
    size_t line_count;
    std::shared_ptr<const TexLinesWithoutRepeats> value;  // null: not worth keeping
  };
  std::vector<Entry> without_repeats;
};

FrameTraceMemo::FrameTraceMemo() : m_impl(std::make_unique<Impl>()) {}
FrameTraceMemo::FrameTraceMemo(const FrameTraceMemo&) : m_impl(std::make_unique<Impl>()) {}
FrameTraceMemo& FrameTraceMemo::operator=(const FrameTraceMemo&) {
  std::lock_guard lock(m_impl->mutex);
  m_impl->without_repeats.clear();
  return *this;
}
FrameTraceMemo::~FrameTraceMemo() = default;

std::shared_ptr<const TexLinesWithoutRepeats> FrameTrace::tex_lines_without_repeats(uint64_t modulus) const {
  if (modulus == 0 || (modulus & (modulus - 1)) != 0 || modulus > (uint64_t(1) << 20))
    throw Error("tex_lines_without_repeats: the modulus must be a power of two up to 2^20, not " + std::to_string(modulus));
  FrameTraceMemo::Impl& m = *memo.m_impl;
  // One thread derives; the others replaying the frame wait for it rather
  // than derive it again.
  std::lock_guard lock(m.mutex);
  for (const auto& e : m.without_repeats)
    if (e.modulus == modulus && e.tiles == tiles.data() && e.records == tiles.size() && e.lines == tex_lines.data() &&
        e.line_count == tex_lines.size())
      return e.value;
  std::erase_if(m.without_repeats, [&](const auto& e) { return e.modulus == modulus; });
  const uint64_t mask = modulus - 1;
  // Per index modulo M, the last line and the record it was read in (+1:
  // zero is no record), so that nothing is reset between records.
  std::vector<TexLine> last_line(modulus);
  std::vector<uint32_t> last_record(modulus, 0);
  const auto each_kept = [&](auto&& keep) {
    for (size_t r = 0; r < tiles.size(); ++r) {
      const TileWork& t = tiles[r];
      const uint32_t stamp = uint32_t(r + 1);
      for (uint64_t i = t.tex_begin, end = t.tex_begin + t.tex_count; i < end; ++i) {
        const TexLine l = tex_lines[i];
        const uint64_t k = tex_line_index(l) & mask;
        if (last_record[k] == stamp && last_line[k] == l) continue;
        last_record[k] = stamp;
        last_line[k] = l;
        keep(r, l);
      }
    }
  };
  uint64_t kept = 0;
  if (tiles.size() < UINT32_MAX) each_kept([&](size_t, TexLine) { ++kept; });
  std::shared_ptr<TexLinesWithoutRepeats> out;
  if (tiles.size() < UINT32_MAX && kept * 2 < tex_lines.size()) {
    out = std::make_shared<TexLinesWithoutRepeats>();
    out->modulus = modulus;
    out->lines.reserve(kept);
    out->begin.assign(tiles.size() + 1, 0);
    std::fill(last_record.begin(), last_record.end(), 0u);
    // begin[r + 1] counts record r's lines first, then the counts are summed.
    each_kept([&](size_t r, TexLine l) {
      out->lines.push_back(l);
      ++out->begin[r + 1];
    });
    for (size_t r = 0; r < tiles.size(); ++r) out->begin[r + 1] += out->begin[r];
  }
  m.without_repeats.push_back({modulus, tiles.data(), tiles.size(), tex_lines.data(), tex_lines.size(), out});
  return out;
}

}  // namespace oovr
