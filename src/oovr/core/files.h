// Files in and out, checked (docs/reliability.md).
//
// Inputs are read only from regular files of bounded size: a FIFO would
// block a reader for ever, /dev/zero would fill its memory, a directory
// would read as nothing. Outputs are written aside, flushed, checked and
// renamed into place, so that a full disk or a failing device is an error
// naming the file, never a silent empty or truncated file; paths are
// checked before the work that produces them, and two outputs of one run
// may not share a path.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace oovr {

// Reads `path` whole when it is a regular file of at most `max_bytes`,
// without blocking and (unless `follow_links`) without following a final
// link; never throws. The readers below, and the trace cache, which turns
// a failure into a miss, are built on it.
struct FileRead {
  enum class Failure { none, missing, unreadable, not_regular, too_large };
  Failure failure = Failure::none;
  std::string why;    // what is wrong, for a message ("it is a directory", the system's reason)
  uint64_t size = 0;  // the file's size, once known
  std::string bytes;  // the file, when nothing failed
};
FileRead read_regular_file(const std::string& path, uint64_t max_bytes, bool follow_links = true);

// oovr's folder `name` among the user's caches: $XDG_CACHE_HOME/oovr/NAME,
// else ~/.cache/oovr/NAME, else oovr-NAME in the temporary folder (the
// trace cache's traces, imported captures, captured games).
std::string user_cache_folder(const std::string& name);

// Reads `path` whole. `what` names the input in messages ("configuration",
// "image"); an Error says what is wrong with the path otherwise.
std::string read_input_file(const std::string& path, const std::string& what, uint64_t max_bytes);
// The same checks without reading, for readers that open the file
// themselves (libzip, assimp). Returns the file's size.
uint64_t check_input_file(const std::string& path, const std::string& what, uint64_t max_bytes);

// Checks, before any work, that `path` can be written: not empty, not a
// directory, in a folder that exists and can be written (or an existing
// device such as /dev/stdout).
void check_output_path(const std::string& path, const std::string& what);
// Writes `bytes` to `path`: a regular file through a temporary file in the
// same folder, flushed, synced and renamed over it; an existing device or
// FIFO directly. Throws Error naming the path and the system's reason
// (e.g. "No space left on device").
void write_output_file(const std::string& path, std::string_view bytes, const std::string& what);

// The outputs one run writes: claim() throws when two of them are the same
// file (however the paths are spelled).
class OutputPaths {
 public:
  void claim(const std::string& path, const std::string& what);

 private:
  std::vector<std::pair<std::string, std::string>> m_claimed;  // (normalised path, what)
};

// Flushes standard output and throws Error when anything written to it was
// lost (a full device, a closed pipe).
void check_stdout();

}  // namespace oovr
