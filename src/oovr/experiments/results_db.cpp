#include "oovr/experiments/results_db.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <tuple>

#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/experiments/sweep.h"
#include "oovr/run/result_json.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

namespace {

// The index reports and the paper's document read metrics by (ResultsDb::bulk).
constexpr const char* kMetricsIndex = "CREATE INDEX IF NOT EXISTS metrics_by_name ON metrics(metric, location)";

constexpr const char* kSchemaName = "oovr.results.db";

// The fixed columns of runs, which a swept key may not shadow.
const char* const kRunColumns[] = {"id",      "sweep", "position", "scene",  "scheme", "resolution",   "frame",
                                   "frames",  "aniso", "config",   "status", "error",  "oovr_version", "git_commit",
                                   "command", "host",  "started",  "wall_s", "result", "checksum"};

// What a sweep's row holds, hashed (its checksum column).
std::string sweep_checksum(const std::string& name, const std::string& file, const std::string& definition,
                           const std::string& keys, int64_t points, const std::string& command) {
  return stable_id(nlohmann::json::array({name, file, definition, keys, points, command}).dump());
}

std::string quoted(const std::string& identifier) {
  std::string s = "\"";
  for (char c : identifier) {
    if (c == '"') s += '"';
    s += c;
  }
  return s + "\"";
}

// One prepared statement, finalised on scope exit.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql, const std::string& path) : m_db(db), m_path(path) {
    if (sqlite3_prepare_v2(db, sql.c_str(), int(sql.size()), &m_stmt, nullptr) != SQLITE_OK) fail();
  }
  ~Statement() { sqlite3_finalize(m_stmt); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, const std::string& v) {
    check(sqlite3_bind_text(m_stmt, i, v.data(), int(v.size()), SQLITE_TRANSIENT));
    return *this;
  }
  Statement& bind_blob(int i, const std::string& v) {
    check(sqlite3_bind_blob(m_stmt, i, v.data(), int(v.size()), SQLITE_TRANSIENT));
    return *this;
  }
  Statement& bind(int i, double v) {
    check(sqlite3_bind_double(m_stmt, i, v));
    return *this;
  }
  Statement& bind(int i, int64_t v) {
    check(sqlite3_bind_int64(m_stmt, i, v));
    return *this;
  }
  Statement& bind(int i, const nlohmann::json& v) {
    if (v.is_number_integer()) return bind(i, int64_t(v.get<int64_t>()));
    if (v.is_number()) return bind(i, v.get<double>());
    if (v.is_string()) return bind(i, v.get<std::string>());
    if (v.is_boolean()) return bind(i, int64_t(v.get<bool>()));
    check(sqlite3_bind_null(m_stmt, i));
    return *this;
  }
  // True while there is a row.
  bool step() {
    const int rc = sqlite3_step(m_stmt);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) fail();
    return false;
  }
  void reset() {
    sqlite3_reset(m_stmt);
    sqlite3_clear_bindings(m_stmt);
  }
  std::string text(int col) const {
    const auto* p = sqlite3_column_text(m_stmt, col);
    return p ? std::string(reinterpret_cast<const char*>(p), size_t(sqlite3_column_bytes(m_stmt, col))) : std::string();
  }
  std::string blob(int col) const {
    const void* p = sqlite3_column_blob(m_stmt, col);
    return p ? std::string(static_cast<const char*>(p), size_t(sqlite3_column_bytes(m_stmt, col))) : std::string();
  }
  double real(int col) const { return sqlite3_column_double(m_stmt, col); }
  int64_t integer(int col) const { return sqlite3_column_int64(m_stmt, col); }
  nlohmann::json value(int col) const {
    switch (sqlite3_column_type(m_stmt, col)) {
      case SQLITE_INTEGER: return integer(col);
      case SQLITE_FLOAT: return real(col);
      case SQLITE_NULL: return nullptr;
      default: return text(col);
    }
  }
  int columns() const { return sqlite3_column_count(m_stmt); }
  std::string column_name(int col) const { return sqlite3_column_name(m_stmt, col); }

 private:
  void check(int rc) const {
    if (rc != SQLITE_OK) fail();
  }
  [[noreturn]] void fail() const { throw Error("results database '" + m_path + "': " + sqlite3_errmsg(m_db)); }
  sqlite3* m_db;
  std::string m_path;
  sqlite3_stmt* m_stmt = nullptr;
};

// `path` as SQLite and open() are given it: "./" in front of a relative
// path, so that SQLite never reads it as a URI ("file:...") or as no file
// (":memory:"). A link, or something other than a plain file, is refused;
// so is a missing file when it must exist.
std::string plain_db_path(const std::string& path, bool must_exist) {
  if (path.empty()) throw Error("the results database needs a path");
  const std::string plain = path.front() == '/' ? path : "./" + path;
  struct stat st {};
  const bool exists = ::lstat(plain.c_str(), &st) == 0;
  if (exists && S_ISLNK(st.st_mode))
    throw Error("the results database '" + path + "' is a symbolic link: give the file it points to");
  if (exists && !S_ISREG(st.st_mode)) throw Error("the results database '" + path + "' is not a plain file");
  if (!exists && must_exist) throw Error("no results database '" + path + "'");
  return plain;
}

nlohmann::ordered_json parse_json(const std::string& text, const std::string& what) {
  try {
    return nlohmann::ordered_json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(what + " is not JSON: " + e.what());
  }
}

}  // namespace

ResultsDb::ResultsDb(const std::string& path, Access access, const DatabaseLock* lock) : m_path(path) {
  // SQLite reads "file:..." as a URI and ":memory:" as no file at all (the
  // results gone, or written elsewhere): a relative path is given to it
  // with "./" in front, which it takes as a plain path.
  const std::string plain = plain_db_path(path, access == Access::read_only);
  // The one writer: an exclusive lock on the file, taken before SQLite
  // opens it and released after it closes it (closing a descriptor of the
  // file earlier would drop SQLite's own locks).
  if (access == Access::write && !lock) m_lock = std::make_unique<DatabaseLock>(path);
  const int flags = access == Access::write ? SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOFOLLOW
                                            : SQLITE_OPEN_READONLY | SQLITE_OPEN_NOFOLLOW;
  if (sqlite3_open_v2(plain.c_str(), &m_db, flags, nullptr) != SQLITE_OK) {
    const std::string why = m_db ? sqlite3_errmsg(m_db) : "out of memory";
    sqlite3_close(m_db);
    m_db = nullptr;
    throw Error("cannot open the results database '" + path + "': " + why);
  }
  try {
    // A reader (a report beside a sweep) waits its turn.
    sqlite3_busy_timeout(m_db, 30000);
    int64_t version = 0;
    try {
      Statement s(m_db, "PRAGMA user_version", path);
      if (s.step()) version = s.integer(0);
    } catch (const Error&) {
      throw Error("'" + path + "' is not an oovr results database (SQLite: " + sqlite3_errmsg(m_db) + ")");
    }
    bool has_tables = false;
    {
      Statement s(m_db, "SELECT count(*) FROM sqlite_master", path);
      if (s.step()) has_tables = s.integer(0) > 0;
    }
    if (!has_tables && access == Access::read_only) throw Error("'" + path + "' is not an oovr results database (it is empty)");
    if (has_tables) {
      bool ours = has_table("meta");
      if (ours) {
        Statement s(m_db, "SELECT value FROM meta WHERE key = 'schema'", path);
        ours = s.step() && s.text(0) == kSchemaName;
      }
      if (!ours)
        throw Error("'" + path + "' is an SQLite database, but not one of oovr's results (no meta table naming " + kSchemaName +
                    ")");
      if (version > kResultsDbVersion)
        throw Error("the results database '" + path + "' has schema version " + std::to_string(version) +
                    ", newer than this oovr's " + std::to_string(kResultsDbVersion) + ": use a newer oovr");
      if (version < 1) throw Error("the results database '" + path + "' has no schema version (damaged?)");
    }
    if (access == Access::read_only) return;
    exec("PRAGMA foreign_keys = ON");
    exec("PRAGMA synchronous = FULL");
    exec("BEGIN IMMEDIATE");
    exec("CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL)");
    exec(std::string("INSERT OR IGNORE INTO meta VALUES ('schema', '") + kSchemaName + "')");
    exec(
        "CREATE TABLE IF NOT EXISTS sweeps(name TEXT PRIMARY KEY, file TEXT NOT NULL, definition TEXT NOT NULL, "
        "swept_keys TEXT NOT NULL, points INTEGER NOT NULL, command TEXT NOT NULL, checksum TEXT)");
    exec(
        "CREATE TABLE IF NOT EXISTS runs(id TEXT PRIMARY KEY, sweep TEXT NOT NULL, position INTEGER NOT NULL, "
        "scene TEXT NOT NULL, scheme TEXT NOT NULL, resolution TEXT NOT NULL, frame INTEGER NOT NULL, "
        "frames INTEGER NOT NULL, aniso INTEGER NOT NULL, config TEXT NOT NULL, "
        "status TEXT NOT NULL CHECK (status IN ('done', 'failed')), error TEXT NOT NULL, oovr_version TEXT NOT NULL, "
        "git_commit TEXT NOT NULL, command TEXT NOT NULL, host TEXT NOT NULL, started TEXT NOT NULL, wall_s REAL NOT NULL, "
        "result TEXT, checksum TEXT)");
    // Version 1 databases: the checksums' columns added (their rows keep none).
    if (version == 1) {
      exec("ALTER TABLE runs ADD COLUMN checksum TEXT");
      exec("ALTER TABLE sweeps ADD COLUMN checksum TEXT");
    }
    exec(
        "CREATE TABLE IF NOT EXISTS metrics(run TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE, location TEXT NOT NULL, "
        "metric TEXT NOT NULL, value REAL NOT NULL, unit TEXT NOT NULL, ordinal INTEGER, PRIMARY KEY (run, location, metric)) "
        "WITHOUT ROWID");
    // Before version 4 a run's result carried its statistics as well as its
    // rows, so the rows' order was not kept; their ordinal is NULL.
    if (version >= 1 && version < 4 && !has_column("metrics", "ordinal")) exec("ALTER TABLE metrics ADD COLUMN ordinal INTEGER");
    exec(kMetricsIndex);
    // Points being run, and the processes that died running them
    // (sweep_supervise.h); a stored run clears its row.
    exec(
        "CREATE TABLE IF NOT EXISTS in_flight(id TEXT PRIMARY KEY, pid INTEGER NOT NULL, deaths INTEGER NOT NULL, "
        "since TEXT NOT NULL)");
    exec(
        "CREATE TABLE IF NOT EXISTS images(run TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE, kind TEXT NOT NULL, "
        "width INTEGER NOT NULL, height INTEGER NOT NULL, data BLOB NOT NULL, legend TEXT NOT NULL, PRIMARY KEY (run, kind))");
    if (version >= 1 && version < 3) scope_runs_to_schemes();
    exec("PRAGMA user_version = " + std::to_string(kResultsDbVersion));
    exec("COMMIT");
  } catch (...) {
    sqlite3_close(m_db);
    m_db = nullptr;
    throw;
  }
}

ResultsDb::~ResultsDb() { sqlite3_close(m_db); }

DatabaseLock::DatabaseLock(const std::string& path) : m_path(path) {
  const std::string plain = plain_db_path(path, false);
  m_fd = ::open(plain.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK, 0644);
  if (m_fd < 0) throw Error("cannot open the results database '" + path + "': " + std::strerror(errno));
  if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    ::close(m_fd);
    if (e == EWOULDBLOCK)
      throw Error("the results database '" + path +
                  "' is being written by another oovr (a sweep, a collect or the paper's run): wait for it to end, or give "
                  "another database");
    throw Error("cannot lock the results database '" + path + "': " + std::strerror(e));
  }
}

DatabaseLock::~DatabaseLock() { ::close(m_fd); }

void ResultsDb::exec(const std::string& sql) const {
  char* message = nullptr;
  if (sqlite3_exec(m_db, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string why = message ? message : sqlite3_errmsg(m_db);
    sqlite3_free(message);
    // A database file that is something else reads as "file is not a database".
    throw Error("results database '" + m_path + "': " + why);
  }
}

std::set<std::string> ResultsDb::columns() const {
  std::set<std::string> out;
  Statement s(m_db, "SELECT name FROM pragma_table_info('runs')", m_path);
  while (s.step()) out.insert(s.text(0));
  return out;
}

void ResultsDb::add_sweep(const SweepRecord& sw, bool replace_definition) {
  for (const auto& key : sw.swept_keys)
    if (std::find(std::begin(kRunColumns), std::end(kRunColumns), key) != std::end(kRunColumns))
      throw Error("the swept key '" + key + "' has the name of a column of runs: it cannot be a column of its own");
  exec("BEGIN IMMEDIATE");
  try {
    const std::set<std::string> have = columns();
    for (const auto& key : sw.swept_keys)
      if (!have.count(key)) exec("ALTER TABLE runs ADD COLUMN " + quoted(key));
    {
      // One definition per name: a sweep of this name defined otherwise is
      // another sweep (sweep_run.h reconciles an edited file explicitly).
      Statement old(m_db, "SELECT definition FROM sweeps WHERE name = ?", m_path);
      old.bind(1, sw.name);
      if (old.step() && old.text(0) != sw.definition && !replace_definition)
        throw Error("the results database '" + m_path + "' holds a sweep named '" + sw.name +
                    "' with another definition: give the sweep another name, or use another database");
    }
    Statement s(m_db, "INSERT OR REPLACE INTO sweeps VALUES (?, ?, ?, ?, ?, ?, ?)", m_path);
    const std::string keys = nlohmann::json(sw.swept_keys).dump();
    s.bind(1, sw.name).bind(2, sw.file).bind(3, sw.definition).bind(4, keys);
    s.bind(5, int64_t(sw.points)).bind(6, sw.command);
    s.bind(7, sweep_checksum(sw.name, sw.file, sw.definition, keys, int64_t(sw.points), sw.command));
    s.step();
    exec("COMMIT");
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

std::map<std::string, std::string> ResultsDb::run_status() const {
  std::map<std::string, std::string> out;
  Statement s(m_db, "SELECT id, status FROM runs", m_path);
  while (s.step()) out[s.text(0)] = s.text(1);
  return out;
}

std::map<std::string, std::string> ResultsDb::run_commits() const {
  std::map<std::string, std::string> out;
  Statement s(m_db, "SELECT id, git_commit FROM runs", m_path);
  while (s.step()) out[s.text(0)] = s.text(1);
  return out;
}

std::map<std::string, int> ResultsDb::run_positions(const std::string& name) const {
  std::map<std::string, int> out;
  Statement s(m_db, "SELECT id, position FROM runs WHERE sweep = ?", m_path);
  s.bind(1, name);
  while (s.step()) out[s.text(0)] = int(s.integer(1));
  return out;
}

void ResultsDb::set_position(const std::string& id, int position) {
  Statement s(m_db, "UPDATE runs SET position = ? WHERE id = ?", m_path);
  s.bind(1, int64_t(position)).bind(2, id);
  s.step();
}

void ResultsDb::remove(const std::string& id) {
  Statement s(m_db, "DELETE FROM runs WHERE id = ?", m_path);
  s.bind(1, id);
  s.step();
  Statement f(m_db, "DELETE FROM in_flight WHERE id = ?", m_path);  // a writer's database has the table
  f.bind(1, id);
  f.step();
}

ResultsDb::Bulk ResultsDb::bulk(size_t runs) {
  size_t held = 0;
  {
    Statement s(m_db, "SELECT count(*) FROM runs", m_path);
    if (s.step()) held = size_t(s.integer(0));
  }
  if (runs == 0 || runs * 16 < held) return Bulk(nullptr);
  exec("DROP INDEX IF EXISTS metrics_by_name");
  return Bulk(this);
}

ResultsDb::Bulk::~Bulk() {
  if (!m_db) return;
  // A failure here (a full disk) leaves the index to the next writer's open.
  sqlite3_exec(m_db->m_db, kMetricsIndex, nullptr, nullptr, nullptr);
}

void ResultsDb::together(const std::function<void()>& f) {
  if (m_together) throw Error("results database '" + m_path + "': together() within together()");
  exec("BEGIN IMMEDIATE");
  m_together = true;
  try {
    f();
    m_together = false;
    exec("COMMIT");
  } catch (...) {
    m_together = false;
    sqlite3_exec(m_db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

bool ResultsDb::insert(const RunRecord& r) {
  check_run_record(r);
  const bool own = !m_together;  // else together()'s transaction
  if (own) exec("BEGIN IMMEDIATE");
  try {
    {
      Statement s(m_db, "SELECT 1 FROM runs WHERE id = ?", m_path);
      s.bind(1, r.id);
      if (s.step()) {
        if (own) exec("ROLLBACK");
        return false;
      }
    }
    const std::set<std::string> have = columns();
    for (const auto& [key, v] : r.swept)
      if (!have.count(key)) exec("ALTER TABLE runs ADD COLUMN " + quoted(key));
    std::string sql =
        "INSERT INTO runs (id, sweep, position, scene, scheme, resolution, frame, frames, aniso, config, status, error, "
        "oovr_version, git_commit, command, host, started, wall_s, result, checksum";
    for (const auto& [key, v] : r.swept) sql += ", " + quoted(key);
    sql += ") VALUES (?";
    for (size_t i = 1; i < 20 + r.swept.size(); ++i) sql += ", ?";
    sql += ")";
    Statement s(m_db, sql, m_path);
    s.bind(1, r.id).bind(2, r.sweep).bind(3, int64_t(r.position)).bind(4, r.scene).bind(5, r.scheme).bind(6, r.resolution);
    s.bind(7, int64_t(r.frame)).bind(8, int64_t(r.frames)).bind(9, int64_t(r.aniso)).bind(10, r.config.dump());
    s.bind(11, r.status).bind(12, r.error).bind(13, r.oovr_version).bind(14, r.git_commit).bind(15, r.command);
    s.bind(16, r.host).bind(17, r.started).bind(18, r.wall_s);
    s.bind(19, r.result.is_null() ? nlohmann::json(nullptr) : nlohmann::json(r.result.dump()));
    s.bind(20, record_checksum(r));
    int i = 21;
    for (const auto& [key, v] : r.swept) s.bind(i++, v);
    s.step();
    Statement m(m_db, "INSERT INTO metrics (run, location, metric, value, unit, ordinal) VALUES (?, ?, ?, ?, ?, ?)", m_path);
    int64_t ordinal = 0;
    for (const Metric& x : r.metrics) {
      m.bind(1, r.id).bind(2, x.location).bind(3, x.metric).bind(4, x.value).bind(5, x.unit).bind(6, ordinal++);
      m.step();
      m.reset();
    }
    Statement im(m_db, "INSERT INTO images VALUES (?, ?, ?, ?, ?, ?)", m_path);
    for (const RunImage& x : r.images) {
      im.bind(1, r.id).bind(2, x.kind).bind(3, int64_t(x.width)).bind(4, int64_t(x.height)).bind_blob(5, x.data);
      im.bind(6, x.legend);
      im.step();
      im.reset();
    }
    Statement done(m_db, "DELETE FROM in_flight WHERE id = ?", m_path);
    done.bind(1, r.id);
    done.step();
    if (own) exec("COMMIT");
    return true;
  } catch (...) {
    if (own) sqlite3_exec(m_db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void ResultsDb::mark_in_flight(const std::vector<std::string>& ids, int64_t pid) {
  const bool own = !m_together;
  if (own) exec("BEGIN IMMEDIATE");
  try {
    Statement s(m_db,
                "INSERT INTO in_flight VALUES (?, ?, 0, datetime('now')) ON CONFLICT(id) DO UPDATE SET pid = excluded.pid, "
                "since = excluded.since",
                m_path);
    for (const auto& id : ids) {
      s.bind(1, id).bind(2, pid);
      s.step();
      s.reset();
    }
    if (own) exec("COMMIT");
  } catch (...) {
    if (own) sqlite3_exec(m_db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::vector<InFlight> ResultsDb::in_flight() const {
  std::vector<InFlight> out;
  if (!has_table("in_flight")) return out;  // a database no writer of this oovr has opened
  Statement s(m_db, "SELECT id, pid, deaths FROM in_flight ORDER BY id", m_path);
  while (s.step()) out.push_back({s.text(0), s.integer(1), int(s.integer(2))});
  return out;
}

void ResultsDb::add_death(const std::string& id) {
  Statement s(m_db, "UPDATE in_flight SET pid = 0, deaths = deaths + 1 WHERE id = ?", m_path);
  s.bind(1, id);
  s.step();
}

bool ResultsDb::has_column(const std::string& table, const std::string& column) const {
  Statement s(m_db, "SELECT count(*) FROM pragma_table_info(?) WHERE name = ?", m_path);
  s.bind(1, table).bind(2, column);
  return s.step() && s.integer(0) == 1;
}

bool ResultsDb::has_table(const std::string& name) const {
  Statement s(m_db, "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?", m_path);
  s.bind(1, name);
  return s.step() && s.integer(0) == 1;
}

void ResultsDb::scope_runs_to_schemes() {
  // Inside the opening transaction; the metrics', images' and in-flight
  // rows follow their run's new id before it commits.
  exec("PRAGMA defer_foreign_keys = ON");
  std::set<std::string> ids;
  for (const auto& [id, status] : run_status()) ids.insert(id);
  const std::map<std::string, std::string> checksums = stored_checksums();
  for (RunRecord r : runs()) {
    const std::string old = r.id;
    const auto sum = checksums.find(old);
    // A run that is not what was written (its checksum, or for a version 1
    // row its id) stays as it is, for verify() to name.
    if (sum != checksums.end() && sum->second != record_checksum(r)) continue;
    if (stable_id(canonical_setup(r)) != old) continue;
    if (!scope_to_scheme(r) || ids.count(r.id)) continue;
    Statement u(m_db, "UPDATE runs SET id = ?, config = ?, checksum = ? WHERE id = ?", m_path);
    u.bind(1, r.id).bind(2, r.config.dump());
    u.bind(3, sum != checksums.end() ? nlohmann::json(record_checksum(r)) : nlohmann::json(nullptr)).bind(4, old);
    u.step();
    for (const char* table : {"UPDATE metrics SET run = ? WHERE run = ?", "UPDATE images SET run = ? WHERE run = ?",
                              "UPDATE in_flight SET id = ? WHERE id = ?"}) {
      Statement m(m_db, table, m_path);
      m.bind(1, r.id).bind(2, old);
      m.step();
    }
    ids.erase(old);
    ids.insert(r.id);
  }
}

std::map<std::string, std::string> ResultsDb::stored_checksums() const {
  std::map<std::string, std::string> out;
  if (!has_column("runs", "checksum")) return out;  // version 1, read as it is
  Statement s(m_db, "SELECT id, checksum FROM runs", m_path);
  while (s.step())
    if (!s.value(1).is_null()) out[s.text(0)] = s.text(1);
  return out;
}

std::vector<RunRecord> ResultsDb::runs(bool images) const {
  std::vector<RunRecord> out;
  {
    Statement s(m_db, "SELECT * FROM runs ORDER BY id", m_path);
    const std::set<std::string> fixed(std::begin(kRunColumns), std::end(kRunColumns));
    while (s.step()) {
      RunRecord r;
      for (int c = 0; c < s.columns(); ++c) {
        const std::string name = s.column_name(c);
        if (name == "id") r.id = s.text(c);
        else if (name == "sweep") r.sweep = s.text(c);
        else if (name == "position") r.position = int(s.integer(c));
        else if (name == "scene") r.scene = s.text(c);
        else if (name == "scheme") r.scheme = s.text(c);
        else if (name == "resolution") r.resolution = s.text(c);
        else if (name == "frame") r.frame = int(s.integer(c));
        else if (name == "frames") r.frames = int(s.integer(c));
        else if (name == "aniso") r.aniso = int(s.integer(c));
        else if (name == "config") r.config = parse_json(s.text(c), "run " + r.id + "'s config");
        else if (name == "status") r.status = s.text(c);
        else if (name == "error") r.error = s.text(c);
        else if (name == "oovr_version") r.oovr_version = s.text(c);
        else if (name == "git_commit") r.git_commit = s.text(c);
        else if (name == "command") r.command = s.text(c);
        else if (name == "host") r.host = s.text(c);
        else if (name == "started") r.started = s.text(c);
        else if (name == "wall_s") r.wall_s = s.real(c);
        else if (name == "result") {
          if (!s.value(c).is_null()) r.result = parse_json(s.text(c), "run " + r.id + "'s result");
        } else if (!fixed.count(name) && !s.value(c).is_null()) {
          r.swept[name] = s.value(c);
        }
      }
      out.push_back(std::move(r));
    }
  }
  // In the order they were written (a stored result's statistics are read
  // back from them in it); rows of version 3 and before by name.
  Statement m(m_db,
              std::string("SELECT location, metric, value, unit FROM metrics WHERE run = ? ORDER BY ") +
                  (has_column("metrics", "ordinal") ? "ordinal, " : "") + "location, metric",
              m_path);
  Statement im(m_db, "SELECT kind, width, height, data, legend FROM images WHERE run = ? ORDER BY kind", m_path);
  for (RunRecord& r : out) {
    m.bind(1, r.id);
    while (m.step()) r.metrics.push_back({m.text(0), m.text(1), m.real(2), m.text(3)});
    m.reset();
    if (!images) continue;
    im.bind(1, r.id);
    while (im.step()) r.images.push_back({im.text(0), int(im.integer(1)), int(im.integer(2)), im.blob(3), im.text(4)});
    im.reset();
  }
  return out;
}

std::map<std::string, std::string> ResultsDb::sweep_definitions() const {
  std::map<std::string, std::string> out;
  Statement s(m_db, "SELECT name, definition FROM sweeps", m_path);
  while (s.step()) out[s.text(0)] = s.text(1);
  return out;
}

void ResultsDb::verify() const {
  const auto damaged = [&](const std::string& what) {
    throw Error("the results database '" + m_path + "' is damaged: " + what +
                "; it is not used (restore it from a copy, or start a new one)");
  };
  {
    // integrity_check, not quick_check: quick_check leaves out whether each
    // index matches its table, and a bit flipped in the metrics index (a
    // quarter of a small database's live bytes) passed it and gave queries
    // by metric wrong rows. It costs 0.45 s of CPU on the paper's 76 MB
    // database.
    Statement s(m_db, "PRAGMA integrity_check", m_path);
    std::string problems;
    while (s.step())
      if (s.text(0) != "ok") problems += (problems.empty() ? "" : "; ") + printable(s.text(0));
    if (!problems.empty()) damaged("SQLite's integrity_check says " + problems);
  }
  {
    // Metrics and images of no recorded run: every run reads back whole
    // without them, but a query over the metrics table would count them.
    Statement s(m_db, "PRAGMA foreign_key_check", m_path);
    if (s.step()) damaged("the table '" + printable(s.text(0)) + "' holds rows of a run that is not recorded");
  }
  std::set<std::string> sweeps;
  {
    // A version 1 database opened read-only has no checksums (NULL below).
    const bool sums = has_column("sweeps", "checksum");
    Statement s(m_db,
                std::string("SELECT name, swept_keys, points, file, definition, command, ") + (sums ? "checksum" : "NULL") +
                    " FROM sweeps",
                m_path);
    while (s.step()) {
      const std::string name = s.text(0);
      if (!s.value(6).is_null() && s.text(6) != sweep_checksum(name, s.text(3), s.text(4), s.text(1), s.integer(2), s.text(5)))
        damaged("sweep '" + printable(name) + "' is not what was written (its checksum differs)");
      if (!is_sweep_name(name)) damaged("a sweep named '" + printable(name) + "', not a name oovr gives");
      nlohmann::json keys;
      try {
        keys = nlohmann::json::parse(s.text(1));
      } catch (const nlohmann::json::exception&) {
      }
      bool ok = keys.is_array();
      for (const auto& k : keys) ok = ok && k.is_string();
      if (!ok) damaged("sweep '" + name + "' has swept keys that are not a list of names");
      if (s.integer(2) < 1 || s.integer(2) > int64_t(kMaxPoints)) damaged("sweep '" + name + "' has " + s.text(2) + " points");
      sweeps.insert(name);
    }
  }
  if (has_column("metrics", "ordinal")) {
    // The order a run's metrics were written in (their ordinals, 0 to n-1;
    // NULL for rows of version 3 and before): the checksum is over the rows
    // sorted by name, so it does not see the order, which a stored result's
    // statistics are read back in.
    Statement s(m_db,
                "SELECT run, count(*), count(ordinal), min(ordinal), max(ordinal), count(DISTINCT ordinal) FROM metrics "
                "GROUP BY run",
                m_path);
    while (s.step()) {
      const int64_t rows = s.integer(1), ordered = s.integer(2);
      if (ordered == 0) continue;
      if (ordered != rows || s.integer(3) != 0 || s.integer(4) != rows - 1 || s.integer(5) != rows)
        damaged("run " + printable(s.text(0)) + "'s metrics are not in an order oovr writes (their ordinals are not 0 to " +
                std::to_string(rows - 1) + ")");
    }
  }
  for (const InFlight& f : in_flight())
    if (!is_run_id(f.id) || f.deaths < 0 || f.pid < 0) damaged("a point marked in flight that is not one of oovr's");
  const std::map<std::string, std::string> checksums = stored_checksums();
  try {
    for (const RunRecord& r : runs()) {
      if (const auto c = checksums.find(r.id); c != checksums.end() && c->second != record_checksum(r))
        throw Error("run " + printable(r.id) + " is not what was written (its checksum differs)");
      check_run_record(r);
      if (!sweeps.count(r.sweep)) throw Error("run " + r.id + " belongs to a sweep '" + r.sweep + "' that is not recorded");
    }
  } catch (const Error& e) {
    damaged(e.what());
  }
}

// ---------------------------------------------------------------- records

bool is_run_id(const std::string& id) {
  return id.size() == 16 &&
         std::all_of(id.begin(), id.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

std::string record_checksum(const RunRecord& r) {
  RunRecord c = r;
  std::sort(c.metrics.begin(), c.metrics.end(),
            [](const Metric& a, const Metric& b) { return std::tie(a.location, a.metric) < std::tie(b.location, b.metric); });
  std::sort(c.images.begin(), c.images.end(), [](const RunImage& a, const RunImage& b) { return a.kind < b.kind; });
  // The record's JSON form as version 2, which brought checksums, wrote it:
  // a later version number must not change every stored run's checksum.
  nlohmann::ordered_json j = to_json(c);
  j["schema_version"] = 2;
  return stable_id(j.dump());
}

bool scope_to_scheme(RunRecord& r) {
  if (!r.config.is_object()) return false;
  nlohmann::ordered_json kept = nlohmann::ordered_json::object();
  for (const auto& [key, e] : r.config.items())
    if (scheme_reads_key(r.scheme, key)) kept[key] = e;
    else if (r.swept.count(key)) return false;
  if (kept.size() == r.config.size()) return false;
  r.config = std::move(kept);
  r.id = stable_id(canonical_setup(r));
  return true;
}

std::string canonical_setup(const RunRecord& r) {
  // Each key's base value, else its text (result_json's base_value), in
  // key order as the configuration holds them.
  std::map<std::string, nlohmann::ordered_json> sorted;
  if (r.config.is_object())
    for (const auto& [key, e] : r.config.items())
      sorted[key] = e.is_object() && e.contains("base") ? e.at("base") : e.is_object() && e.contains("value") ? e.at("value") : e;
  nlohmann::ordered_json config = nlohmann::ordered_json::object();
  for (const auto& [key, v] : sorted) config[key] = v;
  return canonical_point(r.scene, r.scheme, r.resolution, r.frame, r.frames, r.aniso, config);
}

namespace {

bool is_resolution(const std::string& s) {
  const size_t x = s.find('x');
  const auto digits = [](const std::string& d) {
    return !d.empty() && d.size() <= 5 && d.front() != '0' &&
           std::all_of(d.begin(), d.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  return x != std::string::npos && digits(s.substr(0, x)) && digits(s.substr(x + 1));
}

}  // namespace

void check_run_record(const RunRecord& r) {
  if (!is_run_id(r.id)) throw Error("a run id that is not oovr's (16 hex digits): '" + printable(r.id) + "'");
  const auto bad = [&](const std::string& what) { throw Error("run " + r.id + ": " + what); };
  if (!is_sweep_name(r.sweep)) bad("the sweep name '" + printable(r.sweep) + "' is not one oovr takes");
  for (const auto& [field, value] : {std::pair<const char*, const std::string*>{"scene", &r.scene},
                                     {"scheme", &r.scheme},
                                     {"oovr_version", &r.oovr_version},
                                     {"git_commit", &r.git_commit},
                                     {"host", &r.host},
                                     {"started", &r.started}})
    if (value->empty() || value->size() > kMaxNameChars || has_control_characters(*value))
      bad(std::string(field) + " '" + printable(*value) + "' is empty, too long or holds control characters");
  for (const auto& [field, value] : {std::pair<const char*, const std::string*>{"command", &r.command}, {"error", &r.error}})
    if (has_control_characters(*value, true)) bad(std::string(field) + " holds control characters");
  if (!is_resolution(r.resolution)) bad("resolution '" + printable(r.resolution) + "' is not WIDTHxHEIGHT");
  if (r.position < 0 || size_t(r.position) >= kMaxPoints) bad("position " + std::to_string(r.position));
  if (r.frame < 0 || r.frame > 1'000'000) bad("frame " + std::to_string(r.frame));
  if (r.frames < 1 || r.frames > 100'000) bad(std::to_string(r.frames) + " frames");
  if (r.aniso < 1 || r.aniso > 16) bad("aniso " + std::to_string(r.aniso));
  if (!(std::isfinite(r.wall_s) && r.wall_s >= 0)) bad("wall_s " + format_number(r.wall_s));
  if (!r.config.is_object() || r.config.empty()) bad("no configuration");
  for (const auto& [key, e] : r.config.items()) {
    if (!e.is_object() || !e.contains("value") || !e.at("value").is_string())
      bad("configuration key '" + printable(key) + "' has no value");
    if (e.contains("base") && !(e.at("base").is_number() && std::isfinite(e.at("base").get<double>())))
      bad("configuration key '" + key + "' has a base value that is not a finite number");
  }
  for (const auto& [key, v] : r.swept) {
    if (!r.config.contains(key)) bad("swept key '" + printable(key) + "' is not in its configuration");
    if (!(v.is_string() || (v.is_number() && std::isfinite(v.get<double>()))))
      bad("swept key '" + key + "' has value " + v.dump());
  }
  if (stable_id(canonical_setup(r)) != r.id)
    bad("its setup (scene, scheme, resolution, frames, configuration) is not the one its id names");
  std::set<std::pair<std::string, std::string>> seen;
  for (const Metric& m : r.metrics) {
    if (!seen.insert({m.location, m.metric}).second) bad("metric " + m.location + " " + m.metric + " is given twice");
    if (!std::isfinite(m.value)) bad("metric " + m.location + " " + m.metric + " is not a finite number");
  }
  std::set<std::string> kinds;
  for (const RunImage& im : r.images) {
    if (im.kind != "gpm" && im.kind != "tile_traffic") bad("an image of kind '" + printable(im.kind) + "'");
    if (!kinds.insert(im.kind).second) bad("two images of kind '" + im.kind + "'");
    if (im.width < 1 || im.height < 1 || im.width > 65536 || im.height > 65536)
      bad("a " + std::to_string(im.width) + "x" + std::to_string(im.height) + " image");
  }
  if (r.status == "failed") {
    if (r.error.empty()) bad("failed without an error");
    if (!r.metrics.empty() || !r.result.is_null()) bad("failed, with figures");
  } else if (r.status == "done") {
    if (!r.result.is_object()) bad("done without a result");
    std::vector<Metric> expected;
    try {
      expected = metrics_of(scheme_result_from_stored(r.result, r.metrics));
    } catch (const Error& e) {
      bad(e.what());
    }
    // The figures must be the ones its result gives, exactly.
    std::map<std::pair<std::string, std::string>, const Metric*> stored;
    for (const Metric& m : r.metrics) stored[{m.location, m.metric}] = &m;
    for (const Metric& m : expected) {
      const auto it = stored.find({m.location, m.metric});
      if (it == stored.end()) bad("metric " + m.location + " " + m.metric + ", which its result gives, is missing");
      if (it->second->value != m.value || it->second->unit != m.unit)
        bad("metric " + m.location + " " + m.metric + " is " + format_number(it->second->value) + " " + it->second->unit +
            ", its result gives " + format_number(m.value) + " " + m.unit);
    }
    if (expected.size() != r.metrics.size()) bad("it has metrics its result does not give");
  } else {
    bad("status '" + printable(r.status) + "' is neither done nor failed");
  }
}

// ---------------------------------------------------------------- JSON form

std::string base64_encode(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
    for (int k = 3; k >= 0; --k) out += table[(v >> (6 * k)) & 63];
  }
  if (i < bytes.size()) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::optional<std::string> base64_decode(const std::string& text) {
  if (text.size() % 4 != 0) return std::nullopt;
  const auto digit = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  out.reserve(text.size() / 4 * 3);
  for (size_t i = 0; i < text.size(); i += 4) {
    const bool last = i + 4 == text.size();
    const int pad = last ? (text[i + 3] == '=') + (text[i + 2] == '=') : 0;
    if (pad == 1 && text[i + 2] == '=') return std::nullopt;
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) {
      const int d = k >= 4 - pad ? 0 : digit(text[i + size_t(k)]);
      if (d < 0) return std::nullopt;
      v = v << 6 | uint32_t(d);
    }
    out += char(v >> 16);
    if (pad < 2) out += char((v >> 8) & 255);
    if (pad < 1) out += char(v & 255);
  }
  return out;
}

nlohmann::ordered_json to_json(const RunRecord& r) {
  nlohmann::ordered_json j;
  j["schema"] = "oovr.run";
  j["schema_version"] = kResultsDbVersion;
  j["id"] = r.id;
  j["sweep"] = r.sweep;
  j["position"] = r.position;
  j["scene"] = r.scene;
  j["scheme"] = r.scheme;
  j["resolution"] = r.resolution;
  j["frame"] = r.frame;
  j["frames"] = r.frames;
  j["aniso"] = r.aniso;
  j["swept"] = r.swept;
  j["config"] = r.config;
  j["status"] = r.status;
  j["error"] = r.error;
  j["oovr_version"] = r.oovr_version;
  j["git_commit"] = r.git_commit;
  j["command"] = r.command;
  j["host"] = r.host;
  j["started"] = r.started;
  j["wall_s"] = r.wall_s;
  j["result"] = r.result;
  nlohmann::ordered_json m = nlohmann::ordered_json::array();
  for (const Metric& x : r.metrics) m.push_back({x.location, x.metric, x.value, x.unit});
  j["metrics"] = m;
  nlohmann::ordered_json im = nlohmann::ordered_json::array();
  for (const RunImage& x : r.images)
    im.push_back(
        {{"kind", x.kind}, {"width", x.width}, {"height", x.height}, {"data", base64_encode(x.data)}, {"legend", x.legend}});
  j["images"] = im;
  return j;
}

RunRecord run_record_from_json(const nlohmann::ordered_json& j) {
  try {
    if (j.value("schema", "") != "oovr.run") throw Error("a record that is not an oovr run (no \"schema\": \"oovr.run\")");
    const int64_t version = json_whole(j.at("schema_version"), 1, INT32_MAX, "schema_version");
    if (version > kResultsDbVersion)
      throw Error("a run record of schema version " + std::to_string(version) + ", newer than this oovr's " +
                  std::to_string(kResultsDbVersion));
    RunRecord r;
    r.id = j.at("id").get<std::string>();
    r.sweep = j.at("sweep").get<std::string>();
    r.position = int(json_whole(j.at("position"), 0, int64_t(kMaxPoints) - 1, "position"));
    r.scene = j.at("scene").get<std::string>();
    r.scheme = j.at("scheme").get<std::string>();
    r.resolution = j.at("resolution").get<std::string>();
    r.frame = int(json_whole(j.at("frame"), 0, 1'000'000, "frame"));
    r.frames = int(json_whole(j.at("frames"), 1, 100'000, "frames"));
    r.aniso = int(json_whole(j.at("aniso"), 1, 16, "aniso"));
    if (!j.at("swept").is_object()) throw Error("swept is not an object");
    for (const auto& [k, v] : j.at("swept").items()) r.swept[k] = v;
    r.config = j.at("config");
    r.status = j.at("status").get<std::string>();
    if (r.status != "done" && r.status != "failed")
      throw Error("status '" + printable(r.status) + "' is neither done nor failed");
    r.error = j.at("error").get<std::string>();
    r.oovr_version = j.at("oovr_version").get<std::string>();
    r.git_commit = j.at("git_commit").get<std::string>();
    r.command = j.at("command").get<std::string>();
    r.host = j.at("host").get<std::string>();
    r.started = j.at("started").get<std::string>();
    r.wall_s = json_finite(j.at("wall_s"), "wall_s");
    r.result = j.at("result");
    for (const auto& m : j.at("metrics")) {
      if (!m.is_array() || m.size() != 4) throw Error("a metric that is not [location, metric, value, unit]");
      r.metrics.push_back({m.at(0).get<std::string>(), m.at(1).get<std::string>(), json_finite(m.at(2), "a metric's value"),
                           m.at(3).get<std::string>()});
    }
    for (const auto& x : j.at("images")) {
      RunImage im;
      im.kind = x.at("kind").get<std::string>();
      im.width = int(json_whole(x.at("width"), 1, 65536, "an image's width"));
      im.height = int(json_whole(x.at("height"), 1, 65536, "an image's height"));
      const auto data = base64_decode(x.at("data").get<std::string>());
      if (!data) throw Error("image '" + printable(im.kind) + "' is not base 64");
      im.data = *data;
      im.legend = x.at("legend").get<std::string>();
      r.images.push_back(std::move(im));
    }
    check_run_record(r);                  // as it was written
    if (version < 3) scope_to_scheme(r);  // as version 3 writes it (a SLURM task of an older oovr)
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("a run record that is not oovr's: ") + e.what());
  }
}

std::string swept_text(const RunRecord& r) {
  std::string out;
  for (const auto& [k, v] : r.swept) {
    // As readable as the configuration prints it ("32 GB/s"), else as stored.
    const auto c = r.config.find(k);
    out += " " + k + "=" + (c != r.config.end() && c->contains("value") ? (*c)["value"].get<std::string>() : v.dump());
  }
  return out;
}

}  // namespace oovr
