// Small text helpers shared by the command-line tools.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace oovr {

// "a,b,,c" -> {"a", "b", "c"}: comma-separated items, empty ones dropped.
std::vector<std::string> split_list(const std::string& text);

// "a,b,,c" -> {"a", "b", "", "c"}: the fields between separators, empty
// ones kept (a CSV line without quoting; "" -> {""}).
std::vector<std::string> split_fields(const std::string& text, char separator);

// The extension of a path's file name, lower case, with its dot ("x/A.TGA"
// -> ".tga"; "" without one).
std::string lower_extension(const std::string& path);

// A whole number written in digits only ("12"; not " 12", "+12", "-5",
// "1e3" or "12MB") and within [lo, hi], as environment variables and
// limits take them; nothing otherwise (the caller names what is wrong).
std::optional<uint64_t> parse_whole_number(const std::string& text, uint64_t lo, uint64_t hi);

// The words of a command line joined as a POSIX shell would read them back:
// words with characters the shell treats specially are single-quoted
// ("oovr compare --set 'link.bandwidth=1 TBps'").
std::string shell_command_line(int argc, const char* const* argv);

// `text` safe to write to a terminal: control characters (C0, DEL, and C1
// as UTF-8), which could move the cursor, recolour or retitle it, become
// \xNN (\u0080..\u009f for C1); new lines and tabs stay when `keep_lines`.
std::string printable(std::string_view text, bool keep_lines = false);
// Whether `text` holds a character printable() would escape (printable(text,
// keep_lines) != text, without making the copy).
bool has_control_characters(std::string_view text, bool keep_lines = false);

// `text` as literal Markdown within a line (a table cell, or after a
// line's first word): printable() on one line, and every character that
// Markdown (or the HTML it may hold) reads there as markup escaped with a
// backslash, so that a file name cannot end a table cell, open a link, an
// image, a tag or an entity, or set code or emphasis.
std::string markdown_text(std::string_view text);

// `text` as one field of a CSV line (RFC 4180): printable(), and quoted,
// its quotes doubled, where it holds a comma, a quote or a space at an end.
std::string csv_field(std::string_view text);

}  // namespace oovr
