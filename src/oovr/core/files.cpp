#include "oovr/core/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "oovr/core/error.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

std::string quoted(const std::string& path) { return "'" + path + "'"; }

std::string size_text(uint64_t b) {
  if (b >= (uint64_t(1) << 20)) return std::to_string(b >> 20) + " MiB";
  return std::to_string(b) + " bytes";
}

// Opens `path` as a regular file of at most `max_bytes`: without blocking
// (a FIFO opens at once and is then refused) and, unless `follow_links`,
// without following a final link. Returns the descriptor, or -1 with the
// failure in `r`.
int open_regular(const std::string& path, uint64_t max_bytes, bool follow_links, FileRead& r) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | (follow_links ? 0 : O_NOFOLLOW));
  if (fd < 0) {
    r.failure = errno == ENOENT ? FileRead::Failure::missing : FileRead::Failure::unreadable;
    r.why = std::strerror(errno);
    return -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    r.failure = FileRead::Failure::unreadable;
    r.why = std::strerror(errno);
  } else if (!S_ISREG(st.st_mode)) {
    r.failure = FileRead::Failure::not_regular;
    r.why = S_ISDIR(st.st_mode) ? "it is a directory" : "not a regular file";
  } else if ((r.size = uint64_t(st.st_size)) > max_bytes) {
    r.failure = FileRead::Failure::too_large;
    r.why = "it is " + size_text(r.size) + ", more than the limit of " + size_text(max_bytes);
  } else {
    return fd;
  }
  ::close(fd);
  return -1;
}

// The Error an input that `r` could not read is.
[[noreturn]] void input_error(const std::string& path, const std::string& what, const FileRead& r) {
  const std::string message = "cannot read " + what + " " + quoted(path) + ": " + r.why;
  if (r.failure == FileRead::Failure::missing) throw NotFoundError(message);
  throw Error(message);
}

}  // namespace

FileRead read_regular_file(const std::string& path, uint64_t max_bytes, bool follow_links) {
  FileRead r;
  const int fd = open_regular(path, max_bytes, follow_links, r);
  if (fd < 0) return r;
  r.bytes.assign(size_t(r.size), '\0');
  size_t got = 0;
  while (got < r.bytes.size()) {
    const ssize_t n = ::read(fd, r.bytes.data() + got, r.bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      r.failure = FileRead::Failure::unreadable;
      r.why = std::strerror(errno);
    }
    if (n <= 0) break;
    got += size_t(n);
  }
  ::close(fd);
  if (r.failure == FileRead::Failure::none && got != r.bytes.size()) {
    r.failure = FileRead::Failure::unreadable;
    r.why = "it shrank while being read (" + std::to_string(got) + " of " + std::to_string(r.size) + " bytes)";
  }
  if (r.failure != FileRead::Failure::none) r.bytes.clear();
  return r;
}

uint64_t check_input_file(const std::string& path, const std::string& what, uint64_t max_bytes) {
  if (path.empty()) throw Error("no " + what + " file given (the path is empty)");
  FileRead r;
  const int fd = open_regular(path, max_bytes, true, r);
  if (fd < 0) input_error(path, what, r);
  ::close(fd);
  return r.size;
}

std::string read_input_file(const std::string& path, const std::string& what, uint64_t max_bytes) {
  if (path.empty()) throw Error("no " + what + " file given (the path is empty)");
  FileRead r = read_regular_file(path, max_bytes);
  if (r.failure != FileRead::Failure::none) input_error(path, what, r);
  return std::move(r.bytes);
}

void check_output_path(const std::string& path, const std::string& what) {
  if (path.empty()) throw Error("no path given for the " + what + " (it is empty)");
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_directory(st)) throw Error("cannot write the " + what + " " + quoted(path) + ": it is a directory");
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    // A device or FIFO (/dev/stdout, /dev/null): written in place.
    if (::access(path.c_str(), W_OK) != 0)
      throw Error("cannot write the " + what + " " + quoted(path) + ": " + std::strerror(errno));
    return;
  }
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::is_directory(folder, ec))
    throw Error("cannot write the " + what + " " + quoted(path) + ": the folder " + quoted(folder.string()) + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0)
    throw Error("cannot write the " + what + " " + quoted(path) + ": the folder " + quoted(folder.string()) + ": " +
                std::strerror(errno));
  if (fs::exists(st) && ::access(path.c_str(), W_OK) != 0)
    throw Error("cannot write the " + what + " " + quoted(path) + ": " + std::strerror(errno));
}

namespace {

// Writes all of `bytes` to `fd`; returns 0 or the errno of the failure.
int write_all(int fd, std::string_view bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) return EIO;
    done += size_t(n);
  }
  return 0;
}

}  // namespace

void write_output_file(const std::string& path, std::string_view bytes, const std::string& what) {
  const auto fail = [&](int e) { throw Error("cannot write the " + what + " " + quoted(path) + ": " + std::strerror(e)); };
  if (path.empty()) throw Error("no path given for the " + what + " (it is empty)");
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st)) {
    // A device or FIFO: renaming over it would replace it with a file.
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) fail(errno);
    const int e = write_all(fd, bytes);
    if (::close(fd) != 0 && !e) fail(errno);
    if (e) fail(e);
    return;
  }
  if (fs::is_directory(st)) throw Error("cannot write the " + what + " " + quoted(path) + ": it is a directory");
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail(errno);
  int e = write_all(fd, bytes);
  if (!e && ::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) e = errno;
  if (::close(fd) != 0 && !e) e = errno;
  if (!e && ::rename(tmp.c_str(), path.c_str()) != 0) e = errno;
  if (e) {
    ::unlink(tmp.c_str());
    fail(e);
  }
}

void OutputPaths::claim(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st)) return;  // /dev/null may take several
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) p = fs::path(path).lexically_normal();
  for (const auto& [other, other_what] : m_claimed)
    if (other == p.string())
      throw Error("the " + what + " and the " + other_what + " are both " + quoted(path) + ": give each its own path");
  m_claimed.emplace_back(p.string(), what);
}

void check_stdout() {
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    const int e = errno;
    throw Error(std::string("cannot write to standard output: ") + (e ? std::strerror(e) : "write error"));
  }
}

std::string user_cache_folder(const std::string& name) {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/oovr/" + name;
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/oovr/" + name;
  return (std::filesystem::temp_directory_path() / ("oovr-" + name)).string();
}

}  // namespace oovr
