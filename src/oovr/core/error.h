// Errors that reach the user. Every bad input (file, flag, configuration) is
// reported as one Error whose message names what is wrong; the CLI prints it
// on one line and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace oovr {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace oovr
