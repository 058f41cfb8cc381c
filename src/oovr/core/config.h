// The configuration tree: dotted keys ("link.bandwidth") read from TOML
// presets and overridden on the command line ("--set link.bandwidth=128GBps").
//
// Strict, as in pbrt-v4 and Ramulator 2.1: components read the keys they
// know through typed getters; afterwards check_all_used() reports every key
// nobody read as an error naming it, so a typo can never become a silent
// default. A value of the wrong type is an error naming the key too.
// Defaults live with the component that reads them; resolved() lists every
// value in force, defaults included, for result files.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "oovr/core/units.h"

namespace oovr {

class Config {
 public:
  Config() = default;
  // Reads a TOML file; tables nest keys ("[link] bandwidth = ..." is
  // "link.bandwidth"). Throws Error naming the file, line and problem. Only
  // a regular file of at most 1 MiB is read; keys have at most 32 dotted
  // parts and values nest at most 256 deep; floats must be finite.
  static Config from_toml_file(const std::string& path);
  static Config from_toml_string(const std::string& text, const std::string& name);

  // "key=value": value as TOML would read it (integer, float, true/false),
  // else as a string (e.g. 128GBps). Throws Error when malformed.
  void set(const std::string& assignment);
  void set(const std::string& key, const std::string& value);
  // What set() records as the source of the values it sets: "--set" unless
  // told otherwise (a scheme's own overrides say "scheme NAME").
  void set_source(const std::string& source) { m_set_source = source; }

  bool has(const std::string& key) const { return m_values.count(key) != 0; }

  // The values given (by the file, or set()), read or not: each as set()
  // takes it back and where it came from ("FILE.toml:LINE", "--set"), by
  // key. What copies a preset into a sweep's machine (experiments/sweep.h).
  struct Setting {
    std::string key, text, source;
  };
  std::vector<Setting> settings() const;

  // Counts every read of a key by a getter, in this configuration and in
  // the copies made of it from now on, into `counts`: how a test shows that
  // no setting is parsed twice in a run. Copies share the map: one thread.
  void count_reads(std::shared_ptr<std::map<std::string, int>> counts) { m_reads = std::move(counts); }

  // Numbers in [lo, hi], checked as read, before any narrowing: a value
  // outside is an Error naming the key and the range (never truncated).
  int64_t get_int(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) const;
  double get_double(const std::string& key, double fallback, double lo, double hi) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  // One of `choices`; anything else is an Error listing them.
  std::string get_choice(const std::string& key, const std::string& fallback, std::initializer_list<const char*> choices) const;
  // The same, for choices known only at run time (a registry's names).
  std::string get_choice(const std::string& key, const std::string& fallback, const std::vector<std::string>& choices) const;
  // Strings with units ("1MB"), or plain integers in the base unit.
  Bytes get_bytes(const std::string& key, Bytes fallback) const;
  BytesPerSecond get_bandwidth(const std::string& key, BytesPerSecond fallback) const;
  Seconds get_time(const std::string& key, Seconds fallback) const;
  Hertz get_frequency(const std::string& key, Hertz fallback) const;
  // An energy ("10pJ"), from 0 to `max`.
  Joules get_energy(const std::string& key, Joules fallback, Joules max) const;

  // Throws Error naming every key that no getter read.
  void check_all_used() const;
  // Every key read, with the value in force (defaults included), sorted.
  const std::map<std::string, std::string>& resolved() const { return m_resolved; }
  // Every key read, described: what `oovr config --all` lists and what a
  // result records beside the readable value.
  struct Entry {
    std::string value;           // in force, readable and reading back ("1536 KB")
    std::string fallback;        // the default, in the same form
    std::string source;          // "default", "FILE.toml:LINE" or "--set"
    std::string kind;            // what it takes: "a whole number from 1 to 32", "a size", "one of lru, random"
    std::string unit;            // the base unit of `base` ("B", "B/s", "s", "Hz", "J"; "" for plain numbers)
    std::optional<double> base;  // the value as a number in the base unit (none for strings)
  };
  const std::map<std::string, Entry>& entries() const { return m_entries; }
  // Where the values came from (file names, "--set"), for messages.
  const std::string& origin() const { return m_origin; }

 private:
  enum class Kind { integer, floating, boolean, string };
  struct Value {
    Kind kind = Kind::string;
    std::string text;  // as written (strings without quotes)
    int64_t i = 0;
    double d = 0;
    bool b = false;
    std::string source;  // "file.toml:12" or "--set"
  };
  static void flatten(const void* toml_table, const std::string& prefix, const std::string& file,
                      std::map<std::string, Value>& out);
  const Value* find(const std::string& key) const;
  void record(const std::string& key, const Value* v, Entry e) const;
  [[noreturn]] void type_error(const std::string& key, const Value& v, const char* expected) const;

  std::map<std::string, Value> m_values;
  mutable std::map<std::string, bool> m_used;
  mutable std::map<std::string, std::string> m_resolved;
  mutable std::map<std::string, Entry> m_entries;
  std::string m_origin;
  std::string m_set_source = "--set";
  std::shared_ptr<std::map<std::string, int>> m_reads;  // count_reads (null: not counted)
};

// Every value in force (c.resolved(), after check_config) as TOML lines
// "key = value", numbers and booleans bare: a preset that reads back as
// the same configuration (`oovr config`).
std::string resolved_toml(const Config& c);

// The limits every TOML text oovr reads is held to before toml++ parses it
// (at most 1 MiB, keys of at most 32 dotted parts): configurations and
// sweep files. Throws Error naming `name`.
void check_toml_text(const std::string& text, const std::string& name);

}  // namespace oovr
