// Checksums of bytes that are stored and read back (the trace cache, the
// cache of imported scenes).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace oovr {

// A 64-bit checksum of a payload, 8 bytes a step. Each step is a bijection
// of the state for a fixed word and of the word for a fixed state, so any
// change confined to one word (every flipped bit or byte) always changes
// the result; wider damage goes unnoticed with probability 2^-64.
inline uint64_t checksum64(std::string_view b) {
  constexpr uint64_t p1 = 0x9E3779B185EBCA87ull, p2 = 0xC2B2AE3D27D4EB4Full;
  uint64_t h = 0x27D4EB2F165667C5ull ^ uint64_t(b.size());
  size_t i = 0;
  for (; i + 8 <= b.size(); i += 8) {
    uint64_t w;
    std::memcpy(&w, b.data() + i, 8);
    h = std::rotl(h ^ (w * p2), 31) * p1;
  }
  uint64_t tail = 0;
  std::memcpy(&tail, b.data() + i, b.size() - i);
  h = std::rotl(h ^ (tail * p2), 31) * p1;
  h ^= h >> 33;
  h *= p2;
  h ^= h >> 29;
  return h;
}

}  // namespace oovr
