#include "oovr/core/text.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

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

std::vector<std::string> split_fields(const std::string& text, char separator) {
  std::vector<std::string> f;
  size_t i = 0;
  for (;;) {
    const size_t c = text.find(separator, i);
    f.push_back(text.substr(i, c == std::string::npos ? std::string::npos : c - i));
    if (c == std::string::npos) break;
    i = c + 1;
  }
  return f;
}

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::optional<uint64_t> parse_whole_number(const std::string& text, uint64_t lo, uint64_t hi) {
  // At most 19 digits: every such number fits in 64 bits.
  if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  const uint64_t v = std::stoull(text);
  if (v < lo || v > hi) return std::nullopt;
  return v;
}

std::string shell_command_line(int argc, const char* const* argv) {
  std::string out;
  for (int i = 0; i < argc; ++i) {
    const std::string w = argv[i];
    const bool plain = !w.empty() && w.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                         "_-+=:,./@%") == std::string::npos;
    if (!out.empty()) out += ' ';
    if (plain) {
      out += w;
      continue;
    }
    out += '\'';
    for (const char c : w) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += '\'';
  }
  return out;
}

namespace {

// The bytes of a control character at text[i] that printable() escapes: 1
// (C0, DEL), 2 (C1 as UTF-8) or 0 (none).
size_t control_at(std::string_view text, size_t i, bool keep_lines) {
  const auto c = static_cast<unsigned char>(text[i]);
  if (keep_lines && (c == '\n' || c == '\t')) return 0;
  if (c < 0x20 || c == 0x7f) return 1;
  if (c == 0xc2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
      static_cast<unsigned char>(text[i + 1]) <= 0x9f)
    return 2;
  return 0;
}

}  // namespace

std::string printable(std::string_view text, bool keep_lines) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const size_t n = control_at(text, i, keep_lines);
    if (n == 0) {
      out += text[i];
      continue;
    }
    const auto c = static_cast<unsigned char>(text[i += n - 1]);
    out += n == 1 ? "\\x" : "\\u00";
    out += hex[c >> 4];
    out += hex[c & 15];
  }
  return out;
}

bool has_control_characters(std::string_view text, bool keep_lines) {
  for (size_t i = 0; i < text.size(); ++i)
    if (control_at(text, i, keep_lines)) return true;
  return false;
}

std::string markdown_text(std::string_view text) {
  std::string out;
  for (char c : printable(text)) {
    if (std::string_view("\\`*_[]<>!|&~").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

std::string csv_field(std::string_view text) {
  const std::string p = printable(text);
  const bool quote = p.find_first_of(",\"") != std::string::npos || (!p.empty() && (p.front() == ' ' || p.back() == ' '));
  if (!quote) return p;
  std::string out = "\"";
  for (char c : p) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace oovr
