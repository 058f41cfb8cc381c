// The machine oovr runs on, for what it records (results) and names
// (temporary files other hosts may see in a shared folder).
#pragma once

#include <string>

namespace oovr {

// gethostname(), or "" when the system will not say.
std::string host_name();

}  // namespace oovr
