// Small text helpers shared by the command-line tools.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
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

}  // namespace oovr
