#include "oovr/experiments/results_writer.h"

#include "oovr/core/error.h"

#include <string>
#include <utility>

namespace oovr {

ResultsWriter::ResultsWriter(ResultsDb& db, Stored stored, Marked marked)
    : m_db(db), m_stored(std::move(stored)), m_marked(std::move(marked)), m_thread([this] { loop(); }) {}

ResultsWriter::~ResultsWriter() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_work.notify_all();
  if (m_thread.joinable()) m_thread.join();
}

void ResultsWriter::check() const {
  if (m_error) std::rethrow_exception(m_error);
  // Nothing would write it (a defect of the caller's, not a hang).
  if (m_stop) throw Error("results database '" + m_db.path() + "': a record or mark handed over after its writer finished");
}

void ResultsWriter::record(RunRecord r) {
  std::unique_lock<std::mutex> lock(m_mutex);
  m_done.wait(lock, [&] { return m_error || m_stop || m_records_waiting < kMaxWaiting; });
  check();
  m_waiting.emplace_back(std::move(r));
  ++m_records_waiting;
  ++m_handed;
  lock.unlock();
  m_work.notify_one();
}

void ResultsWriter::mark(std::vector<std::string> ids, int64_t pid, std::vector<size_t> points, bool starting, bool wait) {
  std::unique_lock<std::mutex> lock(m_mutex);
  check();
  m_waiting.emplace_back(Mark{std::move(ids), pid, std::move(points), starting});
  const uint64_t mine = ++m_handed;
  m_work.notify_one();
  if (!wait) return;
  m_done.wait(lock, [&] { return m_error || m_written >= mine; });
  if (m_error) std::rethrow_exception(m_error);
}

void ResultsWriter::finish() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stop = true;
  }
  m_work.notify_all();
  if (m_thread.joinable()) m_thread.join();
  std::lock_guard<std::mutex> lock(m_mutex);
  if (m_error) std::rethrow_exception(m_error);
}

size_t ResultsWriter::commits() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_commits;
}

void ResultsWriter::loop() {
  std::unique_lock<std::mutex> lock(m_mutex);
  for (;;) {
    m_work.wait(lock, [&] { return m_stop || !m_waiting.empty(); });
    if (m_waiting.empty()) return;  // stopped, everything written
    // Everything waiting, in one transaction.
    std::vector<Item> batch;
    batch.swap(m_waiting);
    const bool failed = bool(m_error);
    lock.unlock();
    std::exception_ptr error;
    bool committed = false;
    if (!failed) {
      try {
        m_db.together([&] {
          for (const Item& item : batch) {
            if (const auto* r = std::get_if<RunRecord>(&item)) m_db.insert(*r);
            else m_db.mark_in_flight(std::get<Mark>(item).ids, std::get<Mark>(item).pid);
          }
        });
        committed = true;
      } catch (...) {
        error = std::current_exception();
      }
    }
    // The callbacks, after the commit, in order.
    if (!failed && !error) {
      try {
        for (const Item& item : batch) {
          if (const auto* r = std::get_if<RunRecord>(&item)) {
            if (m_stored) m_stored(*r);
          } else if (m_marked) {
            m_marked(std::get<Mark>(item).points, std::get<Mark>(item).starting);
          }
        }
      } catch (...) {
        error = std::current_exception();
      }
    }
    size_t records = 0;
    for (const Item& item : batch) records += std::holds_alternative<RunRecord>(item);
    lock.lock();
    m_commits += committed;
    if (error && !m_error) m_error = error;
    m_records_waiting -= records;
    m_written += batch.size();
    m_done.notify_all();
  }
}

}  // namespace oovr
