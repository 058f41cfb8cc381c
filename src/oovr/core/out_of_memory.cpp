#include "oovr/core/out_of_memory.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include <fmt/core.h>

// The sanitizers bring their own allocator, which reports failures itself;
// oovr's operator new (at the end) is left out of their builds.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define OOVR_SANITIZER_ALLOCATOR 1
#endif
#endif
#else
#define OOVR_SANITIZER_ALLOCATOR 1
#endif

namespace oovr {
namespace {

std::atomic<uint64_t> g_failed_bytes{0};

// The process's peak resident memory (Linux's VmHWM), or 0.
uint64_t peak_resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  uint64_t kb = 0;
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, "VmHWM:", 6) == 0) kb = std::strtoull(line + 6, nullptr, 10);
  std::fclose(f);
  return kb * 1024;
}

}  // namespace

std::string rough_bytes(uint64_t bytes) {
  if (bytes >= (uint64_t(1) << 30)) return fmt::format("{:.1f} GB", double(bytes) / double(uint64_t(1) << 30));
  return fmt::format("{} MB", (bytes + (1 << 20) - 1) >> 20);
}

bool records_failed_allocations() {
#ifdef OOVR_SANITIZER_ALLOCATOR
  return false;
#else
  return true;
#endif
}

uint64_t failed_allocation_bytes() { return g_failed_bytes.load(std::memory_order_relaxed); }

std::string out_of_memory_detail() {
  const uint64_t failed = failed_allocation_bytes(), peak = peak_resident_bytes();
  std::string s;
  if (failed > 0) s = "a request for " + rough_bytes(failed) + " failed";
  if (peak > 0) s += (s.empty() ? "" : ", with ") + rough_bytes(peak) + " of memory in use at the peak";
  return s;
}

std::string out_of_memory_message(const std::string& doing) {
  const std::string detail = out_of_memory_detail();
  return "out of memory " + doing + (detail.empty() ? "" : ": " + detail);
}

}  // namespace oovr

// The global operator new, as the standard library's (malloc, then the new
// handler), recording the size of a request that cannot be met. The other
// forms (arrays, nothrow) call this one; the aligned forms are the library's.
#ifndef OOVR_SANITIZER_ALLOCATOR
void* operator new(std::size_t bytes) {
  for (;;) {
    if (void* p = std::malloc(bytes == 0 ? 1 : bytes)) return p;
    const std::new_handler handler = std::get_new_handler();
    if (!handler) {
      oovr::g_failed_bytes.store(bytes, std::memory_order_relaxed);
      throw std::bad_alloc();
    }
    handler();
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif
