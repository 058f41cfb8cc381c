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

// Kinds of Error that callers other than the CLI tell apart (the Python
// module raises FileNotFoundError and KeyError for them, ValueError for
// any other Error); the CLI prints them as any Error.
//
// An input file, folder or installed data that is not there.
class NotFoundError : public Error {
 public:
  using Error::Error;
};
// A configuration key no component reads (a typo, or a key of another
// version).
class UnknownKeyError : public Error {
 public:
  using Error::Error;
};

}  // namespace oovr
