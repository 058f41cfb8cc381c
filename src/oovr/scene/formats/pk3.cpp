#include "oovr/scene/formats/pk3.h"

#include <zip.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "oovr/core/error.h"
#include "oovr/core/files.h"

namespace oovr {
namespace fs = std::filesystem;

std::string normalize_game_path(std::string path) {
  for (auto& c : path) {
    c = char(std::tolower(static_cast<unsigned char>(c)));
    if (c == '\\') c = '/';
  }
  return path;
}

static std::string zip_code_message(int code) {
  zip_error_t ze;
  zip_error_init_with_code(&ze, code);
  std::string why = zip_error_strerror(&ze);
  zip_error_fini(&ze);
  return why;
}

struct Pk3FileSystem::Impl {
  struct Entry {
    size_t archive;
    zip_uint64_t index;
    zip_uint64_t size;
  };
  std::vector<zip_t*> archives;
  std::map<std::string, Entry> entries;  // normalized path -> newest entry

  ~Impl() {
    for (zip_t* z : archives) zip_discard(z);
  }
};

Pk3FileSystem::Pk3FileSystem(const std::string& directory) : m(std::make_unique<Impl>()) {
  std::error_code ec;
  if (!fs::is_directory(directory, ec)) throw NotFoundError("game directory '" + directory + "' does not exist");
  for (const auto& e : fs::directory_iterator(directory, ec)) {
    if (normalize_game_path(e.path().extension().string()) == ".pk3") m_archive_paths.push_back(e.path().string());
  }
  if (m_archive_paths.empty()) throw NotFoundError("game directory '" + directory + "' holds no .pk3 archives");
  // Engine order: ascending by name, case-insensitively; later ones win.
  std::sort(m_archive_paths.begin(), m_archive_paths.end(), [](const std::string& a, const std::string& b) {
    return normalize_game_path(fs::path(a).filename().string()) < normalize_game_path(fs::path(b).filename().string());
  });
  for (size_t a = 0; a < m_archive_paths.size(); ++a) {
    // Only a regular file is opened (a FIFO named *.pk3 would block).
    (void)check_input_file(m_archive_paths[a], "archive", uint64_t(64) << 30);
    int err = 0;
    zip_t* z = zip_open(m_archive_paths[a].c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &err);
    if (!z) throw Error("cannot open archive '" + m_archive_paths[a] + "': " + zip_code_message(err));
    m->archives.push_back(z);
    const zip_int64_t n = zip_get_num_entries(z, 0);
    for (zip_int64_t i = 0; i < n; ++i) {
      zip_stat_t st;
      if (zip_stat_index(z, zip_uint64_t(i), 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME) || !(st.valid & ZIP_STAT_SIZE))
        throw Error("archive '" + m_archive_paths[a] + "' has an unreadable entry " + std::to_string(i));
      const std::string path = normalize_game_path(st.name);
      if (!path.empty() && path.back() == '/') continue;  // directory
      m->entries[path] = {a, zip_uint64_t(i), st.size};
    }
  }
}

Pk3FileSystem::~Pk3FileSystem() = default;

bool Pk3FileSystem::exists(const std::string& path) const { return m->entries.count(normalize_game_path(path)) != 0; }

std::string Pk3FileSystem::archive_of(const std::string& path) const {
  const auto it = m->entries.find(normalize_game_path(path));
  return it == m->entries.end() ? std::string() : m_archive_paths[it->second.archive];
}

std::optional<std::vector<uint8_t>> Pk3FileSystem::read(const std::string& path, uint64_t max_bytes) const {
  const auto it = m->entries.find(normalize_game_path(path));
  if (it == m->entries.end()) return std::nullopt;
  const auto& e = it->second;
  const std::string where = "'" + path + "' in archive '" + m_archive_paths[e.archive] + "'";
  if (e.size > max_bytes)
    throw Error(where + " is " + std::to_string(e.size) + " bytes, more than the " + std::to_string(max_bytes) + " allowed");
  zip_file_t* f = zip_fopen_index(m->archives[e.archive], e.index, 0);
  if (!f) throw Error("cannot read " + where + ": " + zip_strerror(m->archives[e.archive]));
  std::vector<uint8_t> data(e.size);
  zip_uint64_t got = 0;
  while (got < e.size) {
    const zip_int64_t r = zip_fread(f, data.data() + got, e.size - got);
    if (r <= 0) {
      const std::string why = zip_file_strerror(f);
      zip_fclose(f);
      throw Error("cannot read " + where + ": " + (r < 0 ? why : "unexpected end of data"));
    }
    got += zip_uint64_t(r);
  }
  // libzip checks an entry's CRC when a read reaches its end, not when the
  // declared size has been read: read once more, expecting the end (a pk3
  // entry with a bad CRC once loaded).
  uint8_t extra = 0;
  if (const zip_int64_t r = zip_fread(f, &extra, 1); r != 0) {
    const std::string why = r < 0 ? zip_file_strerror(f) : "more data than its declared size";
    zip_fclose(f);
    throw Error("cannot read " + where + ": " + why);
  }
  if (const int rc = zip_fclose(f); rc != 0) throw Error("cannot read " + where + ": " + zip_code_message(rc));
  return data;
}

std::vector<std::string> Pk3FileSystem::list(const std::string& prefix, const std::string& suffix) const {
  std::vector<std::string> out;
  const std::string p = normalize_game_path(prefix), s = normalize_game_path(suffix);
  for (auto it = m->entries.lower_bound(p); it != m->entries.end() && it->first.compare(0, p.size(), p) == 0; ++it)
    if (it->first.size() >= s.size() && it->first.compare(it->first.size() - s.size(), s.size(), s) == 0)
      out.push_back(it->first);
  return out;
}

}  // namespace oovr
