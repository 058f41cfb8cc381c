// Stores a sweep's records in its database on a thread of its own, several
// to a transaction. A worker that stored its record itself held every other
// worker (one writer) for the length of a transaction, most of it the
// metrics_by_name index's pages written at the commit: on 16 cores the
// 10,000-point study ran at the writer's pace, not the simulation's
// (docs/performance.md, "Storing the records"). Here a worker hands its
// record over and goes on to its next point; the writer takes whatever has
// been handed over since its last commit and stores it in one transaction
// (ResultsDb::together), so that the busier the workers, the larger and the
// cheaper per record its transactions.
//
// Records and marks (ResultsDb::mark_in_flight) are written in the order
// they were handed over. A mark that a point has started, with the process
// running it, is waited for: when the point runs, its mark is on disk and
// so is everything handed over before it, the records of the points the
// worker ran before included. The supervisor of a sweep's child processes
// (sweep_supervise.h) needs both: when a child dies, the points marked as
// its own are the ones it was running (one, when it runs one at a time).
// After each commit, `marked` is called for its marks and `stored` for its
// records, in order, one call at a time, on the writer's thread. The first
// error (the database's, or a callback's) stops the writing: what is handed
// over after it is not written, and the next hand-over, wait or finish()
// throws it.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "oovr/experiments/results_db.h"

namespace oovr {

class ResultsWriter {
 public:
  using Stored = std::function<void(const RunRecord&)>;
  using Marked = std::function<void(const std::vector<size_t>& points, bool starting)>;

  // Writes into `db`, which nothing else may use until finish() returns.
  ResultsWriter(ResultsDb& db, Stored stored = {}, Marked marked = {});
  // Writes what was handed over, then stops; an error then is dropped (call
  // finish() to see it).
  ~ResultsWriter();
  ResultsWriter(const ResultsWriter&) = delete;
  ResultsWriter& operator=(const ResultsWriter&) = delete;

  // Hands a record over (ResultsDb::insert). Waits only while kMaxWaiting
  // records wait to be written.
  void record(RunRecord r);
  // Hands a mark over (ResultsDb::mark_in_flight of `ids` with `pid`); with
  // `wait`, returns once it is committed. `points` and `starting` are passed
  // on to `marked`.
  void mark(std::vector<std::string> ids, int64_t pid, std::vector<size_t> points, bool starting, bool wait);
  // Returns once everything handed over is written and the writer has
  // stopped; throws the first error.
  void finish();

  // Records that may wait to be written before record() waits for room (a
  // run's record is tens to hundreds of kilobytes).
  static constexpr size_t kMaxWaiting = 64;
  // Commits made so far (for tests: records handed over at once share them).
  size_t commits() const;

 private:
  struct Mark {
    std::vector<std::string> ids;
    int64_t pid;
    std::vector<size_t> points;
    bool starting;
  };
  using Item = std::variant<RunRecord, Mark>;
  void loop();
  void check() const;  // throws the first error, or that it stopped (the lock held)

  ResultsDb& m_db;
  Stored m_stored;
  Marked m_marked;
  mutable std::mutex m_mutex;
  std::condition_variable m_work;        // something to write, or stop
  std::condition_variable m_done;        // something written, room made, or an error
  std::vector<Item> m_waiting;           // handed over, in order, not yet taken by the writer
  size_t m_records_waiting = 0;          // records handed over and not yet written (or dropped after an error)
  uint64_t m_handed = 0, m_written = 0;  // items handed over, and written (or dropped after an error)
  size_t m_commits = 0;
  bool m_stop = false;
  std::exception_ptr m_error;
  std::thread m_thread;
};

}  // namespace oovr
