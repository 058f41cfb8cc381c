// The machine oovr runs on, for what it records (results) and names
// (temporary files other hosts may see in a shared folder), and the memory
// it may still use.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace oovr {

// gethostname(), or "" when the system will not say.
std::string host_name();

// Runs a program (words quoted for the shell) and waits for it: its exit
// status (127: not found; 128 + N: killed by signal N), with what it printed
// on both streams appended to `output`. Throws Error when it cannot start a
// shell at all.
int run_command(const std::vector<std::string>& words, std::string& output);

// The bytes this process may still allocate before the kernel refuses or
// kills it, and what bounds them ("the cgroup's memory.max"): the least of
// the machine's available memory and swap (/proc/meminfo), the room left
// under this process's cgroup's limit (v2 memory.max, v1
// memory.limit_in_bytes: containers, SLURM jobs) and under RLIMIT_AS.
// Where none can be read, UINT64_MAX and "".
struct MemoryRoom {
  uint64_t bytes = UINT64_MAX;
  std::string bound;
};
MemoryRoom memory_room();

// Throws Error("<what> needs about N, more than the M this process may
// still use (<bound>)") when `bytes` exceed memory_room(): asked before a
// large allocation, so that it is an error rather than a SIGKILL from the
// OOM killer under a cgroup's limit.
void check_memory_room(uint64_t bytes, const std::string& what);

}  // namespace oovr
