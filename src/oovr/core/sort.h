// Sorts for the simulator's hot paths.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace oovr {

// Sorts entries whose `first` is a pair of 32-bit numbers by that pair,
// keeping the order of entries with equal pairs: what std::stable_sort
// gives, by two counting passes (on the pair's second, then its first)
// where both numbers are below about four times the entries, as a frame's
// objects and tiles are against its records; by std::stable_sort else.
template <class Entry>
void stable_sort_by_pair(std::vector<Entry>& v) {
  const size_t n = v.size();
  uint32_t high = 0, low = 0;
  for (const Entry& e : v) {
    high = std::max<uint32_t>(high, e.first.first);
    low = std::max<uint32_t>(low, e.first.second);
  }
  const size_t most = 4 * n + 65536;
  if (n < 64 || high >= most || low >= most) {
    std::stable_sort(v.begin(), v.end(), [](const Entry& a, const Entry& b) { return a.first < b.first; });
    return;
  }
  std::vector<Entry> other(n);
  std::vector<size_t> at;
  // One stable counting pass of `from` into `to` by digit(e) in [0, top].
  const auto pass = [&](auto digit, uint32_t top, const std::vector<Entry>& from, std::vector<Entry>& to) {
    at.assign(size_t(top) + 2, 0);
    for (const Entry& e : from) ++at[size_t(digit(e)) + 1];
    for (size_t d = 1; d < at.size(); ++d) at[d] += at[d - 1];
    for (const Entry& e : from) to[at[size_t(digit(e))]++] = e;
  };
  pass([](const Entry& e) { return uint32_t(e.first.second); }, low, v, other);
  pass([](const Entry& e) { return uint32_t(e.first.first); }, high, other, v);
}

}  // namespace oovr
