// Deterministic random numbers for procedural content. std:: distributions
// are implementation-defined, so scenes generated with them could differ
// between standard libraries; these functions are defined bit for bit.
#pragma once

#include <cstdint>

namespace oovr {

// SplitMix64 (Steele, Lea, Flood 2014): a stateless mix of a 64-bit value.
constexpr uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed) : m_state(seed) {}
  uint64_t next() { return mix64(m_state++ * 0x632be59bd9b4e019ull); }
  // Uniform in [0, 1) with 24 bits, exactly representable as float.
  float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n).
  uint32_t below(uint32_t n) { return uint32_t((next() >> 32) * n >> 32); }

 private:
  uint64_t m_state;
};

}  // namespace oovr
