#include "oovr/core/text.h"

#include <algorithm>

namespace oovr {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> v;
  for (size_t i = 0; i <= text.size();) {
    const size_t comma = std::min(text.find(',', i), text.size());
    if (comma > i) v.push_back(text.substr(i, comma - i));
    i = comma + 1;
  }
  return v;
}

}  // namespace oovr
