// The progress of a sweep's points (oovr sweep, oovr paper): points done,
// failed, time left. On a terminal, one line redrawn in place; otherwise (a
// log, a pipe, a CI job) one plain line per event. And StatusLine: what a
// single simulation is doing (oovr simulate, oovr compare).
#pragma once

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include "oovr/core/text.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/sweep_schedule.h"

namespace oovr::cli {

inline std::string clock_time(double seconds) {
  const long s = long(seconds + 0.5);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

class Progress {
 public:
  explicit Progress(size_t total) : m_total(total), m_tty(isatty(fileno(stderr)) != 0) {}
  void set_total(size_t total) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_total = total;
  }

  void status(const std::string& what) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_status = printable(what);
    if (m_tty) draw();
    else fmt::print(stderr, "  {}\n", m_status);
  }
  void point(const RunRecord& r) {
    std::lock_guard<std::mutex> lock(m_mutex);
    ++(r.status == "done" ? m_done : m_failed);
    m_ends.push_back(elapsed());
    if (m_tty) {
      if (r.status != "done") {
        clear();
        fmt::print(stderr, "  failed: {} ({}, {}, {}): {}\n", r.id, printable(r.scene), printable(r.scheme), r.resolution,
                   printable(r.error));
      }
      draw();
      return;
    }
    fmt::print(stderr, "  [{}/{}] {} {} {} {}{} ({:.1f} s){}; {}\n", m_done + m_failed, m_total, r.status, printable(r.scene),
               printable(r.scheme), r.resolution, printable(swept_text(r)), r.wall_s,
               r.error.empty() ? "" : ": " + printable(r.error), left());
    std::fflush(stderr);
  }
  void finish() {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_tty) clear();
  }
  size_t done() const { return m_done; }
  size_t failed() const { return m_failed; }
  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count(); }

 private:
  // The time left at the recent rate or the whole run's, the slower
  // (estimate_seconds_left: a sweep's late points are often its costly ones).
  std::string left() const {
    const double now = elapsed(), rest = estimate_seconds_left(m_ends, m_total, now);
    if (std::isnan(rest)) return clock_time(now) + " elapsed";
    return fmt::format("{} elapsed, about {} left", clock_time(now), clock_time(rest));
  }
  void clear() { fmt::print(stderr, "\r\033[K"); }
  void draw() {
    const size_t finished = m_done + m_failed;
    const int width = 24;
    const int filled = m_total ? int(double(width) * double(finished) / double(m_total)) : width;
    std::string bar(size_t(filled), '#');
    bar.resize(size_t(width), '.');
    std::string line = fmt::format("  [{}] {}/{} points, {} failed, {}", bar, finished, m_total, m_failed, left());
    if (!m_status.empty() && finished < m_total) line += " (" + m_status + ")";
    clear();
    fmt::print(stderr, "{}", line.substr(0, 160));
    std::fflush(stderr);
  }

  size_t m_total, m_done = 0, m_failed = 0;
  std::vector<double> m_ends;  // when each point ended, seconds from the start
  bool m_tty;
  std::string m_status;
  std::mutex m_mutex;
  std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
};

// What `oovr simulate` or `oovr compare` is doing while it works (loading a
// level, rendering traces, simulating the schemes), on a terminal only: one
// line redrawn in place with the time elapsed, cleared before the results
// are printed. Nothing when stderr is not a terminal, so that logs and
// scripts see the results alone.
class StatusLine {
 public:
  StatusLine() : m_tty(isatty(fileno(stderr)) != 0) {}
  ~StatusLine() { clear(); }
  StatusLine(const StatusLine&) = delete;
  StatusLine& operator=(const StatusLine&) = delete;

  bool on() const { return m_tty; }
  void show(const std::string& what) {
    if (!m_tty) return;
    std::lock_guard<std::mutex> lock(m_mutex);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    fmt::print(stderr, "\r\033[K  {}", (printable(what) + " (" + clock_time(s) + ")").substr(0, 150));
    std::fflush(stderr);
    m_shown = true;
  }
  void clear() {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (!m_shown) return;
    fmt::print(stderr, "\r\033[K");
    std::fflush(stderr);
    m_shown = false;
  }

 private:
  bool m_tty, m_shown = false;
  std::mutex m_mutex;
  std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
};

}  // namespace oovr::cli
