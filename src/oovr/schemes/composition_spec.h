// What sort-last schemes send to the final frame's owners, and how
// (composition.h explains the keys), apart from the Composer so that the
// machine's specification (machine_spec.h) can hold it.
#pragma once

#include <cstdint>

#include "oovr/core/config.h"

namespace oovr {

// How the GPMs' sub-images reach the final frame (sort_last.composition,
// a setting of the schemes that take an algorithm).
enum class CompositionAlgorithm : uint8_t {
  scheme,       // the scheme's own (not configured)
  gather,       // every pixel to the root, GPM 0, as each piece of work ends
  direct_send,  // to its vertical strip's owner, as each piece of work ends
  binary_swap,  // at the end, log2 rounds of pairwise half-exchanges
  pairwise,     // at the end, N-1 rounds, each GPM sending to one and receiving from one
};
const char* composition_algorithm_name(CompositionAlgorithm a);

struct CompositionSpec {
  bool depth = false;      // colour and depth sent (else colour only)
  bool per_pixel = false;  // per passed fragment (else per line touched)
  static CompositionSpec from_config(const Config& c);
};

}  // namespace oovr
