#include "oovr/schemes/conservation.h"

#include <algorithm>

#include "oovr/core/error.h"

namespace oovr {

namespace {

constexpr int64_t kNoDraw = -2;    // a unit that is not a draw
constexpr int64_t kUnbound = -1;   // a draw no work has run under yet
constexpr uint16_t kMost = 65535;  // counts saturate here

void bump(uint16_t& v) {
  if (v < kMost) ++v;
}

std::string times(uint64_t n) { return n == 1 ? "once" : n == 2 ? "twice" : std::to_string(n) + " times"; }

}  // namespace

RunLedger::RunLedger(std::vector<const FrameTrace*> frames) : m_frames(std::move(frames)) {
  for (const FrameTrace* f : m_frames) {
    m_times.emplace_back(f->tiles.size(), 0);
    m_fb.emplace_back(f->tiles.size(), -1);
    m_composed.emplace_back(f->tiles.size(), 0);
  }
}

void RunLedger::allow_repeats(int times) {
  if (times < 1 || times > 1000) throw Error("a scheme may repeat a record 1 to 1000 times, not " + std::to_string(times));
  m_repeats = times;
}

void RunLedger::received(int unit) {
  if (unit < 0) return;
  if (size_t(unit) >= m_draw_object.size()) m_draw_object.resize(size_t(unit) + 1, kNoDraw);
  m_draw_object[size_t(unit)] = kUnbound;
}

void RunLedger::work(int gpm, int draw, uint32_t object, const char* what) {
  const int64_t bound = draw >= 0 && size_t(draw) < m_draw_object.size() ? m_draw_object[size_t(draw)] : kNoDraw;
  if (bound == kUnbound) {
    m_draw_object[size_t(draw)] = object;
    return;
  }
  if (bound == int64_t(object)) return;
  if (m_draw_breaches++ == 0) {
    m_draw_breach = "object " + std::to_string(object) + "'s " + what + " ran on GPM " + std::to_string(gpm);
    if (bound == kNoDraw)
      m_draw_breach +=
          draw < 0 ? ", whose front end had received no draw" : " under unit " + std::to_string(draw) + ", not a draw";
    else m_draw_breach += " under the draw its front end received for object " + std::to_string(bound);
  }
}

RunLedger::Where RunLedger::find(const TileWork& r) const {
  for (size_t k = 0; k < m_frames.size(); ++k) {
    const std::vector<TileWork>& t = m_frames[k]->tiles;
    if (!t.empty() && &r >= t.data() && &r < t.data() + t.size()) return {int(k), size_t(&r - t.data())};
  }
  return {};
}

std::string RunLedger::describe(const TileWork& r) {
  return "object " + std::to_string(r.object) + " (" + (r.eye ? "right" : "left") + " eye, tile " + std::to_string(r.tile_x) +
         "," + std::to_string(r.tile_y) + ", " + std::to_string(r.covered) + " fragments covered)";
}

void RunLedger::rasterised(const FrameTrace& frame, const TileWork& r, int gpm, int draw, int colour_fb) {
  work(gpm, draw, r.object, "tile work");
  // The record's place in `frame` (the frame replayed last, found again
  // only when another is): a record of another frame, or of none, breaks
  // the law either way.
  if (m_last_frame >= m_frames.size() || m_frames[m_last_frame] != &frame)
    m_last_frame = size_t(std::find(m_frames.begin(), m_frames.end(), &frame) - m_frames.begin());
  const std::vector<TileWork>& t = frame.tiles;
  if (m_last_frame >= m_frames.size() || t.empty() || &r < t.data() || &r >= t.data() + t.size()) {
    // Replayed against a frame it is not of: its texture lines would be
    // another frame's.
    if (m_frame_breaches++ == 0)
      m_frame_breach = describe(r) + " was rasterised on GPM " + std::to_string(gpm) + " as part of a frame it is not of";
    return;
  }
  const size_t record = size_t(&r - t.data());
  uint16_t& n = m_times[m_last_frame][record];
  if (n == 0) m_fb[m_last_frame][record] = int16_t(colour_fb);
  bump(n);
}

void RunLedger::composed(const TileWork& r) {
  const Where w = find(r);
  if (w.frame < 0) {
    ++m_stray_composed;
    return;
  }
  bump(m_composed[size_t(w.frame)][w.record]);
}

void RunLedger::check(const std::string& scheme, int frames_in_flight) const {
  const auto breach = [&](const char* law, const std::string& what, uint64_t count, const std::string& of) {
    std::string m = "scheme '" + scheme + "' breaks a conservation law (" + law + "): " + what;
    if (count > 1) m += " (and " + std::to_string(count - 1) + " more " + of + ")";
    throw Error(m);
  };
  if (m_draw_breaches)
    breach("each draw's work runs under a draw its GPM received for it", m_draw_breach, m_draw_breaches, "pieces of work");
  if (m_stray_composed)
    breach("every pixel composed once", std::to_string(m_stray_composed) + " records composed that are of no frame of the run", 1,
           "");
  if (m_frame_breaches) breach("every covered fragment rasterised once per eye", m_frame_breach, m_frame_breaches, "records");
  const size_t in_flight = size_t(std::clamp(frames_in_flight, 0, int(m_frames.size())));
  // Fragments: once per record with coverage, for the frames that complete.
  std::string first;
  uint64_t count = 0;
  for (size_t k = 0; k < m_frames.size(); ++k) {
    const std::vector<TileWork>& t = m_frames[k]->tiles;
    const uint16_t allowed = k < in_flight ? uint16_t(m_repeats) : 0;
    for (size_t i = 0; i < t.size(); ++i) {
      const uint16_t n = m_times[k][i];
      std::string what;
      if (n == 0 && t[i].covered > 0 && k < in_flight) what = "was never rasterised";
      else if (n > allowed && k < in_flight)
        what = "was rasterised " + times(n) + (m_repeats > 1 ? ", more than the scheme declared (" + times(m_repeats) + ")" : "");
      else if (n > 0 && k >= in_flight)
        what = "was rasterised, but the run completes " + std::to_string(in_flight) + " frame" + (in_flight == 1 ? "" : "s");
      if (what.empty()) continue;
      if (count++ == 0) first = "frame " + std::to_string(k) + " of the run: " + describe(t[i]) + " " + what;
    }
  }
  if (count) breach("every covered fragment rasterised once per eye", first, count, "records");
  // Pixels: each written record reaches its frame's final framebuffer once.
  for (size_t k = 0; k < in_flight; ++k) {
    const std::vector<TileWork>& t = m_frames[k]->tiles;
    for (size_t i = 0; i < t.size(); ++i) {
      const uint16_t n = m_times[k][i];
      if (n == 0 || t[i].colour_write_mask == 0) continue;
      const int fb = m_fb[k][i];
      const uint16_t c = m_composed[k][i];
      std::string what;
      if (fb >= 0 && size_t(fb) < in_flight && size_t(fb) != k)
        what = "was written into frame " + std::to_string(fb) + "'s final framebuffer";
      else if (size_t(fb) == k && c > 0) what = "was written into the final framebuffer and composed there " + times(c) + " more";
      else if (size_t(fb) != k && c == 0)
        what = "was written into private framebuffer " + std::to_string(fb) + " and never composed";
      else if (size_t(fb) != k && c > n)
        what = "was written into private framebuffer " + std::to_string(fb) + " " + times(n) + " and composed " + times(c);
      if (what.empty()) continue;
      if (count++ == 0) first = "frame " + std::to_string(k) + " of the run: " + describe(t[i]) + " " + what;
    }
  }
  if (count) breach("every pixel of the final frame composed once", first, count, "records");
}

}  // namespace oovr
