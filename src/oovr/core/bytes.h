// Plain values as bytes and back, for what oovr stores and reads back (the
// trace cache, the cache of imported scenes). A read past the end, or a
// count of more items than the bytes left could hold, fails (false)
// before anything is allocated: the bytes are untrusted input.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace oovr {

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
// A count, then the items' bytes.
template <class T, class A>
void put_vector(std::string& out, const std::vector<T, A>& v) {
  put(out, uint64_t(v.size()));
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}
inline void put_string(std::string& out, std::string_view s) {
  put(out, uint64_t(s.size()));
  out.append(s.data(), s.size());
}

class ByteReader {
 public:
  explicit ByteReader(std::string_view s) : m_s(s) {}
  template <class T>
  bool get(T& v) {
    if (left() < sizeof v) return false;
    std::memcpy(&v, m_s.data() + m_at, sizeof v);
    m_at += sizeof v;
    return true;
  }
  // A count of items of at least `min_bytes` each that the bytes left can hold.
  bool get_count(uint64_t& n, uint64_t min_bytes) { return get(n) && n <= left() / (min_bytes ? min_bytes : 1); }
  template <class T, class A>
  bool get_vector(std::vector<T, A>& v) {
    uint64_t n = 0;
    if (!get_count(n, sizeof(T))) return false;
    v.resize(size_t(n));
    if (n) std::memcpy(v.data(), m_s.data() + m_at, size_t(n) * sizeof(T));
    m_at += size_t(n) * sizeof(T);
    return true;
  }
  bool get_bytes(uint64_t n, std::string_view& v) {
    if (n > left()) return false;
    v = m_s.substr(m_at, size_t(n));
    m_at += size_t(n);
    return true;
  }
  bool get_string(std::string& s) {
    uint64_t n = 0;
    std::string_view v;
    if (!get(n) || !get_bytes(n, v)) return false;
    s.assign(v);
    return true;
  }
  size_t left() const { return m_s.size() - m_at; }
  bool done() const { return m_at == m_s.size(); }

 private:
  std::string_view m_s;
  size_t m_at = 0;
};

}  // namespace oovr
