// The results store: one SQLite database per study (docs/results.md, "The
// results database"). A run is one sweep point's outcome, done or failed,
// with what made it (oovr's version and commit, the command, the host, the
// resolved configuration) and its figures in long form (metrics). Each run
// is written in one transaction with its metrics and images, so a process
// killed at any moment leaves whole runs only, and a point is stored at
// most once (its id is the key).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "oovr/run/result_metrics.h"

struct sqlite3;

namespace oovr {

// Bumped when a table or column changes meaning or goes. 2: runs and
// sweeps carry a checksum of what they hold (a database of version 1 is
// given the columns when opened to write; its older rows have none). 3: a
// run's configuration and id hold only the keys its run reads, the
// machine's and its scheme's own (scheme_entries); a database of an older
// version is migrated when opened to write (scope_to_scheme). 4: a run's
// statistics are stored once, as its metrics rows, which keep the order
// they were written in (`ordinal`); its `result` holds the rest
// (stored_result_json). Older rows keep their whole result and no ordinal.
inline constexpr int kResultsDbVersion = 4;

struct RunImage {
  std::string kind;  // "gpm": PNG of the first frame coloured by GPM; "tile_traffic": JSON array of bytes per tile
  int width = 0;     // pixels ("gpm") or tiles ("tile_traffic")
  int height = 0;
  std::string data;    // PNG bytes or JSON text
  std::string legend;  // JSON: {"gpm0": "#e6194b", ...} for "gpm"; {"tile_pixels": 16} for "tile_traffic"
};

struct RunRecord {
  std::string id;
  std::string sweep;
  int position = 0;  // the point's place in its sweep file
  std::string scene, scheme, resolution;
  int frame = 0, frames = 0, aniso = 16;
  // Swept keys' values: numbers in base units where the key has a unit.
  std::map<std::string, nlohmann::json> swept;
  nlohmann::ordered_json config;  // the resolved configuration (result_json's form)
  std::string status;             // "done" or "failed"
  std::string error;
  std::string oovr_version, git_commit, command, host, started;  // started: UTC, ISO 8601
  double wall_s = 0;
  nlohmann::ordered_json result;  // result_json's to_json(SchemeResult), for done runs
  std::vector<Metric> metrics;
  std::vector<RunImage> images;
};

// The record's swept settings as the configuration prints them, each
// " key=value" ("link.bandwidth=32 GB/s"): what progress lines show.
std::string swept_text(const RunRecord& r);

// A record as one line of JSON (the SLURM tasks' result files), with
// "schema": "oovr.run" and the schema version, and back; from_json throws
// Error on a malformed record or one of a newer schema.
nlohmann::ordered_json to_json(const RunRecord& r);
RunRecord run_record_from_json(const nlohmann::ordered_json& j);

struct SweepRecord {
  std::string name, file, definition, command;
  std::vector<std::string> swept_keys;
  size_t points = 0;
};

// Whether `id` has the form of oovr's run ids (16 lowercase hex digits,
// sweep.h's stable_id).
bool is_run_id(const std::string& id);
// The JSON a run's id hashes (sweep.cpp's resolve()), from its record: the
// scene, scheme, resolution, frames and every configuration key's value.
std::string canonical_setup(const RunRecord& r);
// A record written before version 3, when ids hashed every key read, other
// schemes' own included (OO-VR's oo.* in a baseline run), as version 3
// writes it: its configuration without the keys its scheme does not read,
// and the id of that. False, leaving it as it is, when nothing changes or
// a swept key would go (such a record keeps its old id and the point is
// run again under the new one).
bool scope_to_scheme(RunRecord& r);
// Throws Error naming the run and what cannot be in one of oovr's records:
// an id of another form, or not the hash of the record's setup; a name with
// control characters; numbers out of range or not finite; a done run whose
// result is not one of oovr's (result_json.h) or whose metrics are not the
// ones its result gives; duplicated metrics or images.
void check_run_record(const RunRecord& r);
// A hash of everything a record holds (its JSON form, metrics and images in
// a fixed order), stored with it and checked by ResultsDb::verify: a byte
// changed anywhere in a run (a unit's name, a figure) is found.
std::string record_checksum(const RunRecord& r);

// The one writer's lock on a results database: an exclusive flock on the
// file (created when absent), held until destroyed, shared by the children
// this process forks (sweep_supervise.h). Throws Error when another
// process holds it.
class DatabaseLock {
 public:
  explicit DatabaseLock(const std::string& path);
  ~DatabaseLock();
  DatabaseLock(const DatabaseLock&) = delete;
  DatabaseLock& operator=(const DatabaseLock&) = delete;
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
  int m_fd = -1;
};

// A point some process was running: the database's mark, from before it
// ran until its record was stored (sweep_supervise.h).
struct InFlight {
  std::string id;
  int64_t pid = 0;  // the process running it; 0 when none is
  int deaths = 0;   // processes that died running it
};

class ResultsDb {
 public:
  enum class Access {
    // Reads and writes, creating the database when absent; the one writer:
    // a second while this one is open is refused (an exclusive lock on the
    // file, held until it is closed, by this process and its children).
    write,
    // Reads an existing oovr database; changes nothing.
    read_only,
  };
  // Opens the database at `path`: a plain file (never a link, never an
  // SQLite URI or ":memory:"). Throws Error when it is not an oovr results
  // database, one of a newer schema, or (writing) open for writing
  // elsewhere.
  // A writer holding `lock` (of this path) does not take it again.
  explicit ResultsDb(const std::string& path, Access access = Access::write, const DatabaseLock* lock = nullptr);
  ~ResultsDb();
  ResultsDb(const ResultsDb&) = delete;
  ResultsDb& operator=(const ResultsDb&) = delete;

  // Records a sweep and makes sure runs has a column per swept key. A
  // sweep of the same name with another definition is an Error unless
  // `replace_definition` (an edited sweep file, reconciled).
  void add_sweep(const SweepRecord& s, bool replace_definition = false);
  // The runs stored (of any sweep): id -> status ("done" or "failed").
  std::map<std::string, std::string> run_status() const;
  // The git commit of the oovr that made each run: id -> commit.
  std::map<std::string, std::string> run_commits() const;
  // The runs of sweep `name`: id -> position.
  std::map<std::string, int> run_positions(const std::string& name) const;
  // Removes a run with its metrics and images (a failed run to retry).
  void remove(const std::string& id);
  // Moves a run to another position in its sweep (an edited sweep file).
  void set_position(const std::string& id, int position);
  // Writes a run, its metrics and images in one transaction. Returns false
  // (and writes nothing) when a run with its id is there already.
  bool insert(const RunRecord& r);
  // Runs `f`, whose inserts and marks (insert, mark_in_flight) then make one
  // transaction with one commit, not one each: a commit writes every page it
  // changed, and a run's metrics change a page of the metrics_by_name index
  // per metric, so that runs stored one by one cost about two and a half
  // times as much as sixteen at once (docs/performance.md). An exception from `f` rolls
  // them all back and is rethrown. Not nested.
  void together(const std::function<void()>& f);
  // For `runs` runs about to be written: when they are many beside the runs
  // held (at least a sixteenth as many), the metrics_by_name index is
  // dropped until the returned object goes, which builds it again, sorting
  // once what each run's metrics would have put in its pages one by one (a
  // run written with the index kept costs about seven times as much:
  // docs/performance.md). A database left without it (a process killed
  // meanwhile) gets it back when next opened for writing; a reader meanwhile
  // reads the same rows, more slowly.
  class Bulk {
   public:
    ~Bulk();
    Bulk(const Bulk&) = delete;
    Bulk& operator=(const Bulk&) = delete;
    Bulk(Bulk&& o) noexcept : m_db(o.m_db) { o.m_db = nullptr; }

   private:
    friend class ResultsDb;
    explicit Bulk(ResultsDb* db) : m_db(db) {}
    ResultsDb* m_db;  // null: the index was kept
  };
  Bulk bulk(size_t runs);
  // Every run, sorted by id (what two databases are compared by); without
  // `images`, their images are left out (what a reader of figures needs).
  std::vector<RunRecord> runs(bool images = true) const;
  // Checks the whole database before it is resumed, reported or written
  // up: SQLite's integrity_check and foreign_key_check, the sweeps table, and every run
  // (check_run_record, and a sweep of its name recorded). Throws Error
  // naming what is damaged.
  void verify() const;
  // The sweeps recorded: name -> definition.
  std::map<std::string, std::string> sweep_definitions() const;

  // Marks points as being run by process `pid` (0: by none, their deaths
  // kept). A stored record clears its point's mark.
  void mark_in_flight(const std::vector<std::string>& ids, int64_t pid);
  // Every point marked, with the process running it and its deaths.
  std::vector<InFlight> in_flight() const;
  // Counts a death against a point, and says no process runs it.
  void add_death(const std::string& id);
  const std::string& path() const { return m_path; }

 private:
  void exec(const std::string& sql) const;
  // Version 2 and older: every run as scope_to_scheme writes it.
  void scope_runs_to_schemes();
  std::set<std::string> columns() const;
  bool has_table(const std::string& name) const;
  bool has_column(const std::string& table, const std::string& column) const;
  // Each run's stored checksum, for the runs that have one.
  std::map<std::string, std::string> stored_checksums() const;
  bool m_together = false;               // inside together(): inserts and marks join its transaction
  std::unique_ptr<DatabaseLock> m_lock;  // the writer's own lock, released after SQLite closes the file
  std::string m_path;
  sqlite3* m_db = nullptr;
};

// The base-64 form the JSON records carry images in.
std::string base64_encode(const std::string& bytes);
std::optional<std::string> base64_decode(const std::string& text);

}  // namespace oovr
