#include "oovr/core/host.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "oovr/core/error.h"
#include "oovr/core/out_of_memory.h"
#include "oovr/core/text.h"

namespace oovr {

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "";
  return buf;
}

int run_command(const std::vector<std::string>& words, std::string& output) {
  std::vector<const char*> argv;
  for (const auto& w : words) argv.push_back(w.c_str());
  const std::string line = shell_command_line(int(argv.size()), argv.data()) + " 2>&1";
  FILE* p = popen(line.c_str(), "r");
  if (!p) throw Error("cannot run '" + words.front() + "': " + std::strerror(errno));
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) output.append(buf, n);
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

namespace {

// A number from the first line of a small file ("max" and unreadable: none).
bool read_number(const std::string& path, uint64_t& out) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word.empty() || word.find_first_not_of("0123456789") != std::string::npos || word.size() > 19)
    return false;
  out = std::stoull(word);
  return true;
}

// "Key:   123 kB" of /proc/meminfo or /proc/self/status, in bytes.
bool read_kb(const std::string& path, const std::string& key, uint64_t& out) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream words(line.substr(key.size() + 1));
      uint64_t kb = 0;
      if (!(words >> kb)) return false;
      out = kb << 10;
      return true;
    }
  return false;
}

void least(MemoryRoom& room, uint64_t bytes, const std::string& bound) {
  if (bytes < room.bytes) {
    room.bytes = bytes;
    room.bound = bound;
  }
}

}  // namespace

MemoryRoom memory_room() {
  MemoryRoom room;
  uint64_t available = 0, swap = 0;
  if (read_kb("/proc/meminfo", "MemAvailable", available)) {
    (void)read_kb("/proc/meminfo", "SwapFree", swap);
    least(room, available + swap, "the machine's available memory and swap");
  }
  // The cgroup of this process: "0::/path" (v2) or "N:memory:/path" (v1).
  std::ifstream cg("/proc/self/cgroup");
  std::string line;
  while (std::getline(cg, line)) {
    const size_t a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
    uint64_t limit = 0, used = 0;
    if (controllers.empty()) {
      const std::string dir = "/sys/fs/cgroup" + path;
      if (read_number(dir + "/memory.max", limit) && read_number(dir + "/memory.current", used))
        least(room, limit > used ? limit - used : 0, "the cgroup's memory.max, " + rough_bytes(limit));
    } else if (controllers.find("memory") != std::string::npos) {
      const std::string dir = "/sys/fs/cgroup/memory" + path;
      if (read_number(dir + "/memory.limit_in_bytes", limit) && read_number(dir + "/memory.usage_in_bytes", used) &&
          limit < (uint64_t(1) << 60))
        least(room, limit > used ? limit - used : 0, "the cgroup's memory.limit_in_bytes, " + rough_bytes(limit));
    }
  }
  rlimit as{};
  uint64_t vm = 0;
  if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY && read_kb("/proc/self/status", "VmSize", vm))
    least(room, as.rlim_cur > vm ? as.rlim_cur - vm : 0, "ulimit -v (RLIMIT_AS), " + rough_bytes(uint64_t(as.rlim_cur)));
  return room;
}

void check_memory_room(uint64_t bytes, const std::string& what) {
  const MemoryRoom room = memory_room();
  if (bytes > room.bytes)
    throw Error(what + " needs about " + rough_bytes(bytes) + ", more than the " + rough_bytes(room.bytes) +
                " this process may still use (" + room.bound + ")");
}

}  // namespace oovr
