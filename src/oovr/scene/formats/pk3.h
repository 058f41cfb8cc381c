// A Quake 3 virtual file system: every .pk3 (zip) archive of a game
// directory, in engine order, later archives overriding earlier ones for the
// same path (ioquake3 searches the alphabetically last pak first). Paths are
// matched case-insensitively, as the engine does.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace oovr {

class Pk3FileSystem {
 public:
  // Opens every *.pk3 in `directory`. Throws Error naming the archive when
  // one cannot be opened or read, and when the directory has none.
  explicit Pk3FileSystem(const std::string& directory);
  ~Pk3FileSystem();
  Pk3FileSystem(const Pk3FileSystem&) = delete;
  Pk3FileSystem& operator=(const Pk3FileSystem&) = delete;

  bool exists(const std::string& path) const;
  // Reads a whole file; throws Error naming archive and entry when the entry
  // is corrupt or larger than `max_bytes`. nullopt when no archive has it.
  std::optional<std::vector<uint8_t>> read(const std::string& path, uint64_t max_bytes = 256ull << 20) const;
  // Paths (lower case) that start with `prefix` and end with `suffix`, sorted.
  std::vector<std::string> list(const std::string& prefix, const std::string& suffix) const;
  // The archive a path comes from (for messages).
  std::string archive_of(const std::string& path) const;
  const std::vector<std::string>& archives() const { return m_archive_paths; }

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
  std::vector<std::string> m_archive_paths;
};

// Lower-cases and turns backslashes into slashes.
std::string normalize_game_path(std::string path);

}  // namespace oovr
