#include "oovr/schemes/memory_tape.h"

#include <array>

namespace oovr {

namespace {

constexpr size_t kScalars = 10;
// each_field names every field of a unit's traffic: a field added to
// UnitTraffic must be added there too.
static_assert(sizeof(UnitTraffic) == kScalars * sizeof(uint64_t) + 3 * sizeof(std::vector<uint64_t>) + sizeof(PerCategory));

constexpr uint64_t kValueBits = 48, kWide = uint64_t(1) << 15;

// A unit's traffic as one list of fields: its scalars, its bytes per
// category, then per GPM and per link.
template <class T, class F>
void each_field(T& t, F&& f) {
  const std::array<decltype(&t.accesses), kScalars> scalars{
      &t.accesses,   &t.l1_hits,      &t.l2_hits,          &t.remote_hits,       &t.home_l2_hits,
      &t.dram_lines, &t.l2_read_hits, &t.local_dram_reads, &t.remote_dram_reads, &t.remote_hops};
  uint64_t i = 0;
  for (auto* s : scalars) f(i++, *s);
  for (auto& v : t.inter_gpm_bytes) f(i++, v);
  for (auto& v : t.dram_read_bytes) f(i++, v);
  for (auto& v : t.dram_write_bytes) f(i++, v);
  for (auto& v : t.link_bytes) f(i++, v);
}

const char* kind_name(uint8_t k) {
  switch (k) {
    case 0: return "a unit's traffic";
    case 1: return "a value";
    default: return "a frame's end";
  }
}

}  // namespace

void MemoryTape::traffic(uint64_t calls, const UnitTraffic& t) {
  m_index.push_back({calls, m_words.size(), kTraffic});
  const size_t count = m_words.size();
  m_words.push_back(0);
  each_field(t, [&](uint64_t i, uint64_t v) {
    if (!v) return;
    if (v >> kValueBits) {
      m_words.push_back((i | kWide) << kValueBits);
      m_words.push_back(v);
    } else {
      m_words.push_back(i << kValueBits | v);
    }
  });
  m_words[count] = m_words.size() - count - 1;
}

void MemoryTape::value(uint64_t calls, uint64_t v) {
  m_index.push_back({calls, m_words.size(), kValue});
  m_words.push_back(v);
}

void MemoryTape::frame_end(uint64_t calls, FrameEnd e) {
  m_index.push_back({calls, m_frames.size(), kFrameEnd});
  m_frames.push_back(std::move(e));
}

uint64_t MemoryTape::bytes() const {
  uint64_t b = m_index.size() * sizeof(Answer) + m_words.size() * sizeof(uint64_t);
  for (const FrameEnd& f : m_frames) b += sizeof(FrameEnd) + f.tile_inter_gpm_bytes.size() * 8 + f.stats.size() * 96;
  return b;
}

size_t MemoryTape::Player::take(uint64_t calls, uint8_t kind) {
  const std::vector<Answer>& index = m_tape->m_index;
  if (m_next >= index.size())
    throw TapeMismatch(std::string("the run asked for ") + kind_name(kind) + " after the recording's last answer");
  const Answer& a = index[m_next];
  if (a.kind != kind || a.calls != calls)
    throw TapeMismatch("the run's call " + std::to_string(m_next) + " differs from the recording's (" + kind_name(kind) +
                       " where it recorded " + kind_name(a.kind) + ")");
  ++m_next;
  return size_t(a.at);
}

void MemoryTape::Player::traffic(uint64_t calls, UnitTraffic& t) {
  const uint64_t* w = m_tape->m_words.data() + take(calls, kTraffic);
  const uint64_t* end = w + 1 + *w;
  ++w;
  // The fields in order, each set from the next word that names it.
  constexpr uint64_t mask = (uint64_t(1) << kValueBits) - 1;
  each_field(t, [&](uint64_t i, uint64_t& v) {
    v = 0;
    if (w == end) return;
    const uint64_t index = (*w >> kValueBits) & ~kWide;
    if (index != i) return;
    if ((*w >> kValueBits) & kWide) {
      v = w[1];
      w += 2;
    } else {
      v = *w & mask;
      ++w;
    }
  });
  if (w != end) throw TapeMismatch("a unit's traffic on the tape has fields this machine's traffic lacks");
}

uint64_t MemoryTape::Player::value(uint64_t calls) { return m_tape->m_words[take(calls, kValue)]; }

const MemoryTape::FrameEnd& MemoryTape::Player::frame_end(uint64_t calls) { return m_tape->m_frames[take(calls, kFrameEnd)]; }

}  // namespace oovr
