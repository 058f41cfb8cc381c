#include "oovr/experiments/results_db.h"

#include <sqlite3.h>

#include <algorithm>

#include "oovr/core/error.h"

namespace oovr {

namespace {

constexpr const char* kSchemaName = "oovr.results.db";

// The fixed columns of runs, which a swept key may not shadow.
const char* const kRunColumns[] = {"id",      "sweep", "position", "scene",  "scheme", "resolution",   "frame",
                                   "frames",  "aniso", "config",   "status", "error",  "oovr_version", "git_commit",
                                   "command", "host",  "started",  "wall_s", "result"};

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

nlohmann::ordered_json parse_json(const std::string& text, const std::string& what) {
  try {
    return nlohmann::ordered_json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(what + " is not JSON: " + e.what());
  }
}

}  // namespace

ResultsDb::ResultsDb(const std::string& path) : m_path(path) {
  if (sqlite3_open_v2(path.c_str(), &m_db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    const std::string why = m_db ? sqlite3_errmsg(m_db) : "out of memory";
    sqlite3_close(m_db);
    throw Error("cannot open the results database '" + path + "': " + why);
  }
  try {
    // A second writer (oovr sweep --collect beside a report) waits its turn.
    sqlite3_busy_timeout(m_db, 30000);
    int64_t version = 0;
    {
      Statement s(m_db, "PRAGMA user_version", path);
      if (s.step()) version = s.integer(0);
    }
    bool has_tables = false;
    {
      Statement s(m_db, "SELECT count(*) FROM sqlite_master", path);
      if (s.step()) has_tables = s.integer(0) > 0;
    }
    if (has_tables) {
      bool ours = false;
      {
        Statement s(m_db, "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'meta'", path);
        ours = s.step() && s.integer(0) == 1;
      }
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
    }
    exec("PRAGMA foreign_keys = ON");
    exec("PRAGMA synchronous = FULL");
    exec("BEGIN IMMEDIATE");
    exec("CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL)");
    exec(std::string("INSERT OR IGNORE INTO meta VALUES ('schema', '") + kSchemaName + "')");
    exec(
        "CREATE TABLE IF NOT EXISTS sweeps(name TEXT PRIMARY KEY, file TEXT NOT NULL, definition TEXT NOT NULL, "
        "swept_keys TEXT NOT NULL, points INTEGER NOT NULL, command TEXT NOT NULL)");
    exec(
        "CREATE TABLE IF NOT EXISTS runs(id TEXT PRIMARY KEY, sweep TEXT NOT NULL, position INTEGER NOT NULL, "
        "scene TEXT NOT NULL, scheme TEXT NOT NULL, resolution TEXT NOT NULL, frame INTEGER NOT NULL, "
        "frames INTEGER NOT NULL, aniso INTEGER NOT NULL, config TEXT NOT NULL, "
        "status TEXT NOT NULL CHECK (status IN ('done', 'failed')), error TEXT NOT NULL, oovr_version TEXT NOT NULL, "
        "git_commit TEXT NOT NULL, command TEXT NOT NULL, host TEXT NOT NULL, started TEXT NOT NULL, wall_s REAL NOT NULL, "
        "result TEXT)");
    exec(
        "CREATE TABLE IF NOT EXISTS metrics(run TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE, location TEXT NOT NULL, "
        "metric TEXT NOT NULL, value REAL NOT NULL, unit TEXT NOT NULL, PRIMARY KEY (run, location, metric)) WITHOUT ROWID");
    exec("CREATE INDEX IF NOT EXISTS metrics_by_name ON metrics(metric, location)");
    exec(
        "CREATE TABLE IF NOT EXISTS images(run TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE, kind TEXT NOT NULL, "
        "width INTEGER NOT NULL, height INTEGER NOT NULL, data BLOB NOT NULL, legend TEXT NOT NULL, PRIMARY KEY (run, kind))");
    exec("PRAGMA user_version = " + std::to_string(kResultsDbVersion));
    exec("COMMIT");
  } catch (...) {
    sqlite3_close(m_db);
    m_db = nullptr;
    throw;
  }
}

ResultsDb::~ResultsDb() { sqlite3_close(m_db); }

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

void ResultsDb::add_sweep(const SweepRecord& sw) {
  for (const auto& key : sw.swept_keys)
    if (std::find(std::begin(kRunColumns), std::end(kRunColumns), key) != std::end(kRunColumns))
      throw Error("the swept key '" + key + "' has the name of a column of runs: it cannot be a column of its own");
  exec("BEGIN IMMEDIATE");
  try {
    const std::set<std::string> have = columns();
    for (const auto& key : sw.swept_keys)
      if (!have.count(key)) exec("ALTER TABLE runs ADD COLUMN " + quoted(key));
    Statement s(m_db, "INSERT OR REPLACE INTO sweeps VALUES (?, ?, ?, ?, ?, ?)", m_path);
    s.bind(1, sw.name).bind(2, sw.file).bind(3, sw.definition).bind(4, nlohmann::json(sw.swept_keys).dump());
    s.bind(5, int64_t(sw.points)).bind(6, sw.command);
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

void ResultsDb::remove(const std::string& id) {
  Statement s(m_db, "DELETE FROM runs WHERE id = ?", m_path);
  s.bind(1, id);
  s.step();
}

bool ResultsDb::insert(const RunRecord& r) {
  if (r.status != "done" && r.status != "failed") throw Error("run " + r.id + ": status '" + r.status + "'");
  exec("BEGIN IMMEDIATE");
  try {
    {
      Statement s(m_db, "SELECT 1 FROM runs WHERE id = ?", m_path);
      s.bind(1, r.id);
      if (s.step()) {
        exec("ROLLBACK");
        return false;
      }
    }
    const std::set<std::string> have = columns();
    for (const auto& [key, v] : r.swept)
      if (!have.count(key)) exec("ALTER TABLE runs ADD COLUMN " + quoted(key));
    std::string sql =
        "INSERT INTO runs (id, sweep, position, scene, scheme, resolution, frame, frames, aniso, config, status, error, "
        "oovr_version, git_commit, command, host, started, wall_s, result";
    for (const auto& [key, v] : r.swept) sql += ", " + quoted(key);
    sql += ") VALUES (?";
    for (size_t i = 1; i < 19 + r.swept.size(); ++i) sql += ", ?";
    sql += ")";
    Statement s(m_db, sql, m_path);
    s.bind(1, r.id).bind(2, r.sweep).bind(3, int64_t(r.position)).bind(4, r.scene).bind(5, r.scheme).bind(6, r.resolution);
    s.bind(7, int64_t(r.frame)).bind(8, int64_t(r.frames)).bind(9, int64_t(r.aniso)).bind(10, r.config.dump());
    s.bind(11, r.status).bind(12, r.error).bind(13, r.oovr_version).bind(14, r.git_commit).bind(15, r.command);
    s.bind(16, r.host).bind(17, r.started).bind(18, r.wall_s);
    s.bind(19, r.result.is_null() ? nlohmann::json(nullptr) : nlohmann::json(r.result.dump()));
    int i = 20;
    for (const auto& [key, v] : r.swept) s.bind(i++, v);
    s.step();
    Statement m(m_db, "INSERT INTO metrics VALUES (?, ?, ?, ?, ?)", m_path);
    for (const Metric& x : r.metrics) {
      m.bind(1, r.id).bind(2, x.location).bind(3, x.metric).bind(4, x.value).bind(5, x.unit);
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
    exec("COMMIT");
    return true;
  } catch (...) {
    sqlite3_exec(m_db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::vector<RunRecord> ResultsDb::runs() const {
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
  Statement m(m_db, "SELECT location, metric, value, unit FROM metrics WHERE run = ? ORDER BY location, metric", m_path);
  Statement im(m_db, "SELECT kind, width, height, data, legend FROM images WHERE run = ? ORDER BY kind", m_path);
  for (RunRecord& r : out) {
    m.bind(1, r.id);
    while (m.step()) r.metrics.push_back({m.text(0), m.text(1), m.real(2), m.text(3)});
    m.reset();
    im.bind(1, r.id);
    while (im.step()) r.images.push_back({im.text(0), int(im.integer(1)), int(im.integer(2)), im.blob(3), im.text(4)});
    im.reset();
  }
  return out;
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
    if (j.at("schema_version").get<int>() > kResultsDbVersion)
      throw Error("a run record of schema version " + std::to_string(j.at("schema_version").get<int>()) +
                  ", newer than this oovr's " + std::to_string(kResultsDbVersion));
    RunRecord r;
    r.id = j.at("id").get<std::string>();
    r.sweep = j.at("sweep").get<std::string>();
    r.position = j.at("position").get<int>();
    r.scene = j.at("scene").get<std::string>();
    r.scheme = j.at("scheme").get<std::string>();
    r.resolution = j.at("resolution").get<std::string>();
    r.frame = j.at("frame").get<int>();
    r.frames = j.at("frames").get<int>();
    r.aniso = j.at("aniso").get<int>();
    for (const auto& [k, v] : j.at("swept").items()) r.swept[k] = v;
    r.config = j.at("config");
    r.status = j.at("status").get<std::string>();
    if (r.status != "done" && r.status != "failed") throw Error("status '" + r.status + "' is neither done nor failed");
    r.error = j.at("error").get<std::string>();
    r.oovr_version = j.at("oovr_version").get<std::string>();
    r.git_commit = j.at("git_commit").get<std::string>();
    r.command = j.at("command").get<std::string>();
    r.host = j.at("host").get<std::string>();
    r.started = j.at("started").get<std::string>();
    r.wall_s = j.at("wall_s").get<double>();
    r.result = j.at("result");
    for (const auto& m : j.at("metrics"))
      r.metrics.push_back(
          {m.at(0).get<std::string>(), m.at(1).get<std::string>(), m.at(2).get<double>(), m.at(3).get<std::string>()});
    for (const auto& x : j.at("images")) {
      RunImage im;
      im.kind = x.at("kind").get<std::string>();
      im.width = x.at("width").get<int>();
      im.height = x.at("height").get<int>();
      const auto data = base64_decode(x.at("data").get<std::string>());
      if (!data) throw Error("image '" + im.kind + "' is not base 64");
      im.data = *data;
      im.legend = x.at("legend").get<std::string>();
      r.images.push_back(std::move(im));
    }
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
