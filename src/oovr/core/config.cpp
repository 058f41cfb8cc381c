#include "oovr/core/config.h"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "oovr/core/error.h"
#include "oovr/core/files.h"

namespace oovr {
namespace {

std::string format_double(double d) { return format_number(d); }

// A time or frequency printed in `unit` when its parser reads that back as
// the same double, else in the base unit.
std::string format_scaled(double v, double per_unit, const char* unit, const char* base, double (*parse)(const std::string&)) {
  if (const double x = v * per_unit; std::isfinite(x)) {
    const std::string scaled = format_number(x) + unit;
    try {
      if (parse(scaled) == v) return scaled;
    } catch (const Error&) {
    }
  }
  return format_number(v) + base;
}

// Limits on a configuration file's shape, checked on its text before toml++
// parses it: a key of 20,000 dotted parts overflows the parser's stack.
constexpr uint64_t kMaxConfigBytes = uint64_t(1) << 20;
constexpr int kMaxKeyParts = 32;

// Throws Error when a key (in a [table] header, before '=', or inside an
// inline table) has more than kMaxKeyParts dotted parts. Strings and
// comments are skipped; values' dots (1.5) are not counted.
void check_toml_shape(const std::string& text, const std::string& name) {
  int line = 1;
  bool in_key = true;  // at a key: line start, after '{' or ',' in an inline table, in a header
  int parts = 1;
  std::vector<char> open;  // '[' (array) and '{' (inline table) of values
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      if (open.empty()) {
        in_key = true;
        parts = 1;
      }
      continue;
    }
    if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      continue;
    }
    if (c == '"' || c == '\'') {
      const bool multi = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string end = multi ? std::string(3, c) : std::string(1, c);
      size_t j = i + end.size();
      while (j < text.size() && text.compare(j, end.size(), end) != 0) {
        if (c == '"' && text[j] == '\\') ++j;  // an escape in a basic string
        if (j < text.size() && text[j] == '\n') ++line;
        ++j;
      }
      i = std::min(text.size(), j + end.size()) - 1;
      continue;
    }
    if (in_key) {
      if (c == '.' && ++parts > kMaxKeyParts)
        throw Error("bad configuration '" + name + "' line " + std::to_string(line) + ": a key of more than " +
                    std::to_string(kMaxKeyParts) + " dotted parts");
      if (c == '=') in_key = false;
      // An inline table closed where a key could start ("{}", "{a = 1, }").
      if (c == '}' && !open.empty() && open.back() == '{') {
        open.pop_back();
        in_key = false;
      }
      continue;
    }
    if (c == '[' || c == '{') {
      open.push_back(c);
      if (c == '{') {
        in_key = true;
        parts = 1;
      }
    } else if ((c == ']' || c == '}') && !open.empty()) {
      open.pop_back();
    } else if (c == ',' && !open.empty() && open.back() == '{') {
      in_key = true;
      parts = 1;
    }
  }
}

}  // namespace

void check_toml_text(const std::string& text, const std::string& name) {
  if (text.size() > kMaxConfigBytes)
    throw Error("bad configuration '" + name + "': more than " + std::to_string(kMaxConfigBytes >> 20) + " MiB");
  check_toml_shape(text, name);
}

Config Config::from_toml_string(const std::string& text, const std::string& name) {
  Config c;
  c.m_origin = name;
  check_toml_text(text, name);
  try {
    const toml::table t = toml::parse(text, name);
    flatten(&t, "", name, c.m_values);
  } catch (const toml::parse_error& e) {
    std::ostringstream msg;
    msg << "bad configuration '" << name << "' line " << e.source().begin.line << ": " << e.description();
    throw Error(msg.str());
  }
  return c;
}

Config Config::from_toml_file(const std::string& path) {
  return from_toml_string(read_input_file(path, "configuration", kMaxConfigBytes), path);
}

// `toml_table` is a toml::table; the header keeps toml++ out of its includes.
void Config::flatten(const void* toml_table, const std::string& prefix, const std::string& file,
                     std::map<std::string, Value>& out) {
  const auto& t = *static_cast<const toml::table*>(toml_table);
  for (const auto& [k, node] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    const std::string where = file + ":" + std::to_string(node.source().begin.line);
    Value v;
    v.source = where;
    if (const auto* sub = node.as_table()) {
      flatten(sub, key, file, out);
      continue;
    } else if (const auto* i = node.as_integer()) {
      v.kind = Kind::integer;
      v.i = i->get();
      v.d = double(v.i);
      v.text = std::to_string(v.i);
    } else if (const auto* f = node.as_floating_point()) {
      v.kind = Kind::floating;
      v.d = f->get();
      v.text = format_double(v.d);
      if (!std::isfinite(v.d))
        throw Error("bad configuration '" + where + "': key '" + key + "' must be a finite number, not " + v.text);
    } else if (const auto* b = node.as_boolean()) {
      v.kind = Kind::boolean;
      v.b = b->get();
      v.text = v.b ? "true" : "false";
    } else if (const auto* s = node.as_string()) {
      v.kind = Kind::string;
      v.text = s->get();
    } else {
      throw Error("bad configuration '" + where + "': key '" + key + "' has a value of a type oovr does not use (arrays, dates)");
    }
    out[key] = v;
  }
}

void Config::set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw Error("bad setting '" + assignment + "': expected key=value (e.g. link.bandwidth=128GBps)");
  set(assignment.substr(0, eq), assignment.substr(eq + 1));
}

void Config::set(const std::string& key, const std::string& value) {
  for (char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'))
      throw Error("bad setting key '" + key + "': keys are dotted names such as link.bandwidth");
  if (value.empty()) throw Error("bad setting '" + key + "=': the value is empty");
  Value v;
  v.source = m_set_source;
  v.text = value;
  const char* b = value.data();
  const char* e = b + value.size();
  int64_t i = 0;
  double d = 0;
  if (auto r = std::from_chars(b, e, i); r.ec == std::errc() && r.ptr == e) {
    v.kind = Kind::integer;
    v.i = i;
    v.d = double(i);
  } else if (auto rd = std::from_chars(b, e, d); rd.ec == std::errc() && rd.ptr == e && std::isfinite(d)) {
    v.kind = Kind::floating;
    v.d = d;
  } else if (value == "true" || value == "false") {
    v.kind = Kind::boolean;
    v.b = value == "true";
  } else {
    v.kind = Kind::string;
  }
  m_values[key] = v;
  if (m_origin.find(m_set_source) == std::string::npos) m_origin += (m_origin.empty() ? "" : ", ") + m_set_source;
}

std::vector<Config::Setting> Config::settings() const {
  std::vector<Setting> out;
  for (const auto& [key, v] : m_values) out.push_back({key, v.text, v.source});
  return out;
}

const Config::Value* Config::find(const std::string& key) const {
  if (m_reads) ++(*m_reads)[key];
  const auto it = m_values.find(key);
  if (it == m_values.end()) return nullptr;
  m_used[key] = true;
  return &it->second;
}

void Config::record(const std::string& key, const Value* v, Entry e) const {
  e.source = v ? v->source : "default";
  m_resolved[key] = e.value;
  m_entries[key] = std::move(e);
}

void Config::type_error(const std::string& key, const Value& v, const char* expected) const {
  throw Error("configuration key '" + key + "' (" + v.source + ") must be " + expected + ", not '" + v.text + "'");
}

int64_t Config::get_int(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) const {
  const Value* v = find(key);
  int64_t r = fallback;
  if (v) {
    const std::string range = "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi);
    if (v->kind != Kind::integer) type_error(key, *v, range.c_str());
    if (v->i < lo || v->i > hi) type_error(key, *v, range.c_str());
    r = v->i;
  }
  record(key, v,
         {std::to_string(r), std::to_string(fallback), "",
          "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi), "", double(r)});
  return r;
}

double Config::get_double(const std::string& key, double fallback, double lo, double hi) const {
  const Value* v = find(key);
  double r = fallback;
  if (v) {
    const std::string range = "a number from " + format_double(lo) + " to " + format_double(hi);
    if (v->kind != Kind::integer && v->kind != Kind::floating) type_error(key, *v, range.c_str());
    if (!(v->d >= lo && v->d <= hi)) type_error(key, *v, range.c_str());
    r = v->d;
  }
  record(
      key, v,
      {format_double(r), format_double(fallback), "", "a number from " + format_double(lo) + " to " + format_double(hi), "", r});
  return r;
}

bool Config::get_bool(const std::string& key, bool fallback) const {
  const Value* v = find(key);
  bool r = fallback;
  if (v) {
    if (v->kind != Kind::boolean) type_error(key, *v, "true or false");
    r = v->b;
  }
  record(key, v, {r ? "true" : "false", fallback ? "true" : "false", "", "true or false", "", std::nullopt});
  return r;
}

std::string Config::get_string(const std::string& key, const std::string& fallback) const {
  const Value* v = find(key);
  std::string r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a string");
    r = v->text;
  }
  record(key, v, {r, fallback, "", "a string", "", std::nullopt});
  return r;
}

std::string Config::get_choice(const std::string& key, const std::string& fallback,
                               std::initializer_list<const char*> choices) const {
  return get_choice(key, fallback, std::vector<std::string>(choices.begin(), choices.end()));
}

std::string Config::get_choice(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& choices) const {
  const std::string r = get_string(key, fallback);
  std::string list;
  for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
  m_entries[key].kind = "one of " + list;
  for (const std::string& c : choices)
    if (r == c) return r;
  const Value* v = find(key);
  throw Error("configuration key '" + key + "' (" + (v ? v->source : "default") + ") must be one of " + list + ", not '" + r +
              "'");
}

Bytes Config::get_bytes(const std::string& key, Bytes fallback) const {
  const Value* v = find(key);
  Bytes r = fallback;
  if (v) {
    if (v->kind == Kind::integer && v->i >= 0) r = {uint64_t(v->i)};
    else if (v->kind == Kind::string) r = parse_bytes(v->text, "configuration key '" + key + "' (" + v->source + ")");
    else type_error(key, *v, "a size such as 128KB");
  }
  record(key, v, {format_bytes(r), format_bytes(fallback), "", "a size (128KB, 2MiB)", "B", double(r.value)});
  return r;
}

BytesPerSecond Config::get_bandwidth(const std::string& key, BytesPerSecond fallback) const {
  const Value* v = find(key);
  BytesPerSecond r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a bandwidth such as 64GBps");
    r = parse_bandwidth(v->text, "configuration key '" + key + "' (" + v->source + ")");
  }
  record(key, v, {format_bandwidth(r), format_bandwidth(fallback), "", "a bandwidth (64GBps)", "B/s", r.value});
  return r;
}

Seconds Config::get_time(const std::string& key, Seconds fallback) const {
  const Value* v = find(key);
  Seconds r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a time such as 100ns");
    r = parse_time(v->text, "configuration key '" + key + "' (" + v->source + ")");
  }
  const auto print = [](double s) {
    return format_scaled(s, 1e9, "ns", "s", [](const std::string& t) { return parse_time(t, "").value; });
  };
  record(key, v, {print(r.value), print(fallback.value), "", "a time (100ns)", "s", r.value});
  return r;
}

Hertz Config::get_frequency(const std::string& key, Hertz fallback) const {
  const Value* v = find(key);
  Hertz r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a frequency such as 1GHz");
    r = parse_frequency(v->text, "configuration key '" + key + "' (" + v->source + ")");
  }
  const auto print = [](double hz) {
    return format_scaled(hz, 1e-6, "MHz", "Hz", [](const std::string& t) { return parse_frequency(t, "").value; });
  };
  record(key, v, {print(r.value), print(fallback.value), "", "a frequency (1GHz)", "Hz", r.value});
  return r;
}

Joules Config::get_energy(const std::string& key, Joules fallback, Joules max) const {
  const Value* v = find(key);
  Joules r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "an energy such as 10pJ");
    const std::string what = "configuration key '" + key + "' (" + v->source + ")";
    r = parse_energy(v->text, what);
    const auto pj = [](double j) { return format_number(j * 1e12) + " pJ"; };
    if (r.value > max.value) throw Error(what + " must be from 0 to " + pj(max.value) + ", not " + pj(r.value));
  }
  const auto print = [](double j) {
    return format_scaled(j, 1e12, "pJ", "J", [](const std::string& t) { return parse_energy(t, "").value; });
  };
  record(key, v, {print(r.value), print(fallback.value), "", "an energy (10pJ)", "J", r.value});
  return r;
}

void Config::check_all_used() const {
  std::string unknown;
  for (const auto& [k, v] : m_values)
    if (!m_used.count(k)) unknown += (unknown.empty() ? "" : ", ") + ("'" + k + "' (" + v.source + ")");
  if (!unknown.empty()) throw UnknownKeyError("unknown configuration key " + unknown);
}

std::string resolved_toml(const Config& c) {
  std::string out;
  for (const auto& [k, v] : c.resolved()) {
    // Numbers and booleans bare, so they read back as numbers ("1e-05" too).
    double number = 0;
    const auto r = std::from_chars(v.data(), v.data() + v.size(), number);
    const bool bare = v == "true" || v == "false" || (!v.empty() && r.ec == std::errc() && r.ptr == v.data() + v.size());
    out += k + " = " + (bare ? v : "\"" + v + "\"") + "\n";
  }
  return out;
}

}  // namespace oovr
