#include "oovr/core/units.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>

#include "oovr/core/error.h"

namespace oovr {
namespace {

// Splits "64GBps" / "64 GB/s" into 64 and "gbps" (lower case, no spaces or '/').
bool split(const std::string& text, double& number, std::string& unit) {
  size_t i = 0;
  while (i < text.size() && text[i] == ' ') ++i;
  const char* b = text.data() + i;
  const char* e = text.data() + text.size();
  const auto r = std::from_chars(b, e, number);
  if (r.ec != std::errc() || !std::isfinite(number)) return false;
  unit.clear();
  for (const char* p = r.ptr; p < e; ++p) {
    if (*p == ' ' || *p == '/') continue;
    unit += char(std::tolower(static_cast<unsigned char>(*p)));
  }
  return true;
}

// The number of `text` and the factor its unit names in `units`.
std::pair<double, double> lookup(const std::string& text, const std::string& what, const std::map<std::string, double>& units,
                                 const char* expected) {
  double n = 0;
  std::string u;
  if (!split(text, n, u)) throw Error(what + ": '" + text + "' is not a number with a unit (e.g. " + expected + ")");
  const auto it = units.find(u);
  if (it == units.end()) throw Error(what + ": unknown unit '" + u + "' in '" + text + "' (e.g. " + expected + ")");
  if (n < 0) throw Error(what + ": '" + text + "' must not be negative");
  return {n, it->second};
}

}  // namespace

Bytes parse_bytes(const std::string& text, const std::string& what) {
  static const std::map<std::string, double> units = {
      {"b", 1},           {"kb", 1024.0},       {"kib", 1024.0},      {"mb", 1048576.0},
      {"mib", 1048576.0}, {"gb", 1073741824.0}, {"gib", 1073741824.0}};
  const auto [n, scale] = lookup(text, what, units, "128B, 128KB, 1MB");
  const double v = n * scale;
  if (v != std::floor(v) || v > 1e18) throw Error(what + ": '" + text + "' is not a whole number of bytes");
  return {uint64_t(v)};
}

BytesPerSecond parse_bandwidth(const std::string& text, const std::string& what) {
  static const std::map<std::string, double> units = {{"bps", 1},   {"bs", 1},     {"kbps", 1e3}, {"kbs", 1e3},   {"mbps", 1e6},
                                                      {"mbs", 1e6}, {"gbps", 1e9}, {"gbs", 1e9},  {"tbps", 1e12}, {"tbs", 1e12}};
  const auto [n, scale] = lookup(text, what, units, "64GBps, 64 GB/s, 1TBps");
  return {n * scale};
}

Seconds parse_time(const std::string& text, const std::string& what) {
  // Units per second, divided by: "100ns" is exactly the double 100e-9.
  static const std::map<std::string, double> per_second = {{"s", 1}, {"ms", 1e3}, {"us", 1e6}, {"ns", 1e9}, {"ps", 1e12}};
  const auto [n, scale] = lookup(text, what, per_second, "100ns, 1us");
  return {n / scale};
}

Hertz parse_frequency(const std::string& text, const std::string& what) {
  static const std::map<std::string, double> units = {{"hz", 1}, {"khz", 1e3}, {"mhz", 1e6}, {"ghz", 1e9}};
  const auto [n, scale] = lookup(text, what, units, "1GHz, 1500MHz");
  return {n * scale};
}

Joules parse_energy(const std::string& text, const std::string& what) {
  // Units per joule, divided by, as times are: "10pJ" is exactly 10e-12.
  static const std::map<std::string, double> per_joule = {{"j", 1},    {"mj", 1e3},  {"uj", 1e6},
                                                          {"nj", 1e9}, {"pj", 1e12}, {"fj", 1e15}};
  const auto [n, scale] = lookup(text, what, per_joule, "10pJ, 0.5pJ");
  return {n / scale};
}

std::string format_bytes(Bytes b) {
  // Exact, in the largest unit that divides it, so that a printed size
  // (oovr config, result files) reads back as the same number of bytes.
  const uint64_t v = b.value;
  const auto whole = [&](uint64_t unit, const char* name) { return std::to_string(v / unit) + " " + name; };
  if (v >= (1ull << 30) && v % (1ull << 30) == 0) return whole(1ull << 30, "GB");
  if (v >= (1ull << 20) && v % (1ull << 20) == 0) return whole(1ull << 20, "MB");
  if (v >= 1024 && v % 1024 == 0) return whole(1024, "KB");
  return whole(1, "B");
}

std::string format_number(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest form that reads back exactly
  return std::string(buf, r.ptr);
}

std::string format_bandwidth(BytesPerSecond b) {
  // In the largest of TB/s, GB/s and MB/s that reads back exactly, else in B/s.
  for (const auto& [scale, unit] : {std::pair{1e12, " TB/s"}, std::pair{1e9, " GB/s"}, std::pair{1e6, " MB/s"}})
    if (b.value >= scale && (b.value / scale) * scale == b.value) return format_number(b.value / scale) + unit;
  return format_number(b.value) + " B/s";
}

}  // namespace oovr
