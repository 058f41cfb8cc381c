#include "oovr/core/config.h"

#include <toml++/toml.h>

#include <charconv>
#include <fstream>
#include <cmath>
#include <sstream>

#include "oovr/core/error.h"

namespace oovr {
namespace {

std::string format_double(double d) {
  std::ostringstream o;
  o.precision(17);
  o << d;
  return o.str();
}

}  // namespace

Config Config::from_toml_string(const std::string& text, const std::string& name) {
  Config c;
  c.m_origin = name;
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
  std::ifstream in(path);
  if (!in) throw Error("cannot read configuration '" + path + "'");
  std::stringstream buf;
  buf << in.rdbuf();
  return from_toml_string(buf.str(), path);
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
  v.source = "--set";
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
  m_origin += m_origin.empty() ? "--set" : ", --set";
}

const Config::Value* Config::find(const std::string& key) const {
  const auto it = m_values.find(key);
  if (it == m_values.end()) return nullptr;
  m_used[key] = true;
  return &it->second;
}

void Config::record(const std::string& key, const std::string& value) const { m_resolved[key] = value; }

void Config::type_error(const std::string& key, const Value& v, const char* expected) const {
  throw Error("configuration key '" + key + "' (" + v.source + ") must be " + expected + ", not '" + v.text + "'");
}

int64_t Config::get_int(const std::string& key, int64_t fallback) const {
  const Value* v = find(key);
  int64_t r = fallback;
  if (v) {
    if (v->kind != Kind::integer) type_error(key, *v, "a whole number");
    r = v->i;
  }
  record(key, std::to_string(r));
  return r;
}

double Config::get_double(const std::string& key, double fallback) const {
  const Value* v = find(key);
  double r = fallback;
  if (v) {
    if (v->kind != Kind::integer && v->kind != Kind::floating) type_error(key, *v, "a number");
    r = v->d;
  }
  record(key, format_double(r));
  return r;
}

bool Config::get_bool(const std::string& key, bool fallback) const {
  const Value* v = find(key);
  bool r = fallback;
  if (v) {
    if (v->kind != Kind::boolean) type_error(key, *v, "true or false");
    r = v->b;
  }
  record(key, r ? "true" : "false");
  return r;
}

std::string Config::get_string(const std::string& key, const std::string& fallback) const {
  const Value* v = find(key);
  std::string r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a string");
    r = v->text;
  }
  record(key, r);
  return r;
}

std::string Config::get_choice(const std::string& key, const std::string& fallback,
                               std::initializer_list<const char*> choices) const {
  const std::string r = get_string(key, fallback);
  std::string list;
  for (const char* c : choices) {
    if (r == c) return r;
    list += (list.empty() ? "" : ", ") + std::string(c);
  }
  const Value* v = find(key);
  throw Error("configuration key '" + key + "' (" + (v ? v->source : "default") + ") must be one of " + list +
              ", not '" + r + "'");
}

Bytes Config::get_bytes(const std::string& key, Bytes fallback) const {
  const Value* v = find(key);
  Bytes r = fallback;
  if (v) {
    if (v->kind == Kind::integer && v->i >= 0) r = {uint64_t(v->i)};
    else if (v->kind == Kind::string) r = parse_bytes(v->text, "configuration key '" + key + "' (" + v->source + ")");
    else type_error(key, *v, "a size such as 128KB");
  }
  record(key, format_bytes(r));
  return r;
}

BytesPerSecond Config::get_bandwidth(const std::string& key, BytesPerSecond fallback) const {
  const Value* v = find(key);
  BytesPerSecond r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a bandwidth such as 64GBps");
    r = parse_bandwidth(v->text, "configuration key '" + key + "' (" + v->source + ")");
  }
  record(key, format_bandwidth(r));
  return r;
}

Seconds Config::get_time(const std::string& key, Seconds fallback) const {
  const Value* v = find(key);
  Seconds r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a time such as 100ns");
    r = parse_time(v->text, "configuration key '" + key + "' (" + v->source + ")");
  }
  record(key, format_double(r.value * 1e9) + "ns");
  return r;
}

Hertz Config::get_frequency(const std::string& key, Hertz fallback) const {
  const Value* v = find(key);
  Hertz r = fallback;
  if (v) {
    if (v->kind != Kind::string) type_error(key, *v, "a frequency such as 1GHz");
    r = parse_frequency(v->text, "configuration key '" + key + "' (" + v->source + ")");
  }
  record(key, format_double(r.value / 1e6) + "MHz");
  return r;
}

void Config::check_all_used() const {
  std::string unknown;
  for (const auto& [k, v] : m_values)
    if (!m_used.count(k)) unknown += (unknown.empty() ? "" : ", ") + ("'" + k + "' (" + v.source + ")");
  if (!unknown.empty()) throw Error("unknown configuration key " + unknown);
}

}  // namespace oovr
