// Small text helpers shared by the command-line tools.
#pragma once

#include <string>
#include <vector>

namespace oovr {

// "a,b,,c" -> {"a", "b", "c"}: comma-separated items, empty ones dropped.
std::vector<std::string> split_list(const std::string& text);

}  // namespace oovr
