// A scheme's result as JSON, as `oovr simulate --json`, `oovr compare
// --json` and `oovr paper` write it.
#pragma once

#include <nlohmann/json.hpp>

#include "oovr/schemes/i_scheme.h"

namespace oovr {

nlohmann::ordered_json to_json(const SchemeResult& r);

}  // namespace oovr
