// What sort-last schemes send to the final frame's owners (composition.h
// explains the keys), apart from the Composer so that the machine's
// specification (machine_spec.h) can hold it.
#pragma once

#include "oovr/core/config.h"

namespace oovr {

struct CompositionSpec {
  bool depth = false;      // colour and depth sent (else colour only)
  bool per_pixel = false;  // per passed fragment (else per line touched)
  static CompositionSpec from_config(const Config& c);
};

}  // namespace oovr
