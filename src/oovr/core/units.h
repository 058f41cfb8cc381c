// Units in the type (STYLE.md): sizes in bytes, bandwidths in bytes per
// second, times in seconds, frequencies in hertz, energies in joules, and
// their parsing from the strings configurations use ("128KB", "64GBps",
// "100ns", "1GHz", "10pJ").
//
// Sizes use binary multiples (1 KB = 1024 B), as cache and page sizes are
// quoted; bandwidths use decimal ones (1 GB/s = 10^9 B/s), as link and DRAM
// bandwidths are quoted. KiB/MiB/GiB are accepted too.
#pragma once

#include <cstdint>
#include <string>

namespace oovr {

struct Bytes {
  uint64_t value = 0;
  friend bool operator==(Bytes, Bytes) = default;
};
struct BytesPerSecond {
  double value = 0;
};
struct Seconds {
  double value = 0;
};
struct Hertz {
  double value = 0;
};
struct Joules {
  double value = 0;
};
using Cycles = uint64_t;

// Parsers throw Error with `what` (e.g. a configuration key) in the message.
Bytes parse_bytes(const std::string& text, const std::string& what);
BytesPerSecond parse_bandwidth(const std::string& text, const std::string& what);
Seconds parse_time(const std::string& text, const std::string& what);
Hertz parse_frequency(const std::string& text, const std::string& what);
// "10pJ", "0.5 pJ", "1nJ": energies as quoted per bit or per access.
Joules parse_energy(const std::string& text, const std::string& what);

// Printed forms read back by the parsers as the same value: sizes exactly in
// the largest unit that divides them ("128 KB", "1536 KB", "127897 B"),
// numbers in their shortest exact form.
std::string format_bytes(Bytes b);
std::string format_bandwidth(BytesPerSecond b);  // "64 GB/s"
std::string format_number(double v);             // "0.1", "625", "1e-09"

}  // namespace oovr
