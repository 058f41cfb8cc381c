#include "oovr/experiments/sweep.h"

#include <toml++/toml.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"
#include "oovr/core/units.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/run/frames.h"
#include "oovr/run/result_json.h"
#include "oovr/scene/stereo.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

// About what a resolved point holds (its configuration), for the bound on
// what a sweep's points may hold in all: kMaxPoints of them.
constexpr uint64_t kPointBytes = 25'000;
// What a sweep's points may hold in all: kMaxPoints of them, with room for
// their names and settings.
constexpr uint64_t kMaxPointsBytes = kMaxPoints * kPointBytes * 6 / 5;

// What one level of the file (the top level or a [[point]]) says; a field
// left out is taken from the level above.
struct Level {
  std::optional<std::vector<std::string>> scenes, schemes, resolutions;
  std::optional<std::vector<int>> frame, frames, aniso;
  std::optional<std::vector<std::pair<std::string, std::string>>> set;
  std::optional<std::vector<std::pair<std::string, std::vector<std::string>>>> sweep;
};

class Reader {
 public:
  explicit Reader(std::string file) : m_file(std::move(file)) {}

  [[noreturn]] void fail(const toml::node& at, const std::string& what) const {
    throw Error("bad sweep '" + m_file + "' line " + std::to_string(at.source().begin.line) + ": " + what);
  }
  [[noreturn]] void fail(const std::string& what) const { throw Error("bad sweep '" + m_file + "': " + what); }

  // `one` for a single value, or for each of a non-empty list of them.
  template <class F>
  void one_or_list(const toml::node& n, const std::string& key, F one) const {
    if (const auto* a = n.as_array()) {
      if (a->empty()) fail(n, key + " is an empty list");
      for (const auto& x : *a) one(x);
    } else {
      one(n);
    }
  }

  // A string or a non-empty list of strings.
  std::vector<std::string> strings(const toml::node& n, const std::string& key) const {
    std::vector<std::string> out;
    one_or_list(n, key, [&](const toml::node& x) {
      const auto* s = x.as_string();
      if (!s) fail(x, key + " takes strings");
      if (s->get().empty()) fail(x, key + " has an empty name");
      if (s->get().size() > kMaxNameChars)
        fail(x, key + " has a name of more than " + std::to_string(kMaxNameChars) + " characters");
      if (has_control_characters(s->get())) fail(x, key + " has a name with control characters");
      out.push_back(s->get());
    });
    return out;
  }

  // A whole number or a non-empty list of them, each in [lo, hi].
  std::vector<int> integers(const toml::node& n, const std::string& key, int lo, int hi) const {
    std::vector<int> out;
    one_or_list(n, key, [&](const toml::node& x) {
      const auto* i = x.as_integer();
      if (!i) fail(x, key + " takes whole numbers");
      if (i->get() < lo || i->get() > hi)
        fail(x, key + " = " + std::to_string(i->get()) + " is outside " + std::to_string(lo) + " to " + std::to_string(hi));
      out.push_back(int(i->get()));
    });
    return out;
  }

  // A configuration value as `--set` takes it: strings as written, numbers
  // and booleans in TOML's spelling.
  std::string value(const toml::node& n, const std::string& key) const {
    if (const auto* s = n.as_string()) {
      if (s->get().empty()) fail(n, key + " has an empty value");
      if (s->get().size() > kMaxNameChars)
        fail(n, key + " has a value of more than " + std::to_string(kMaxNameChars) + " characters");
      if (has_control_characters(s->get())) fail(n, key + " has a value with control characters");
      return s->get();
    }
    if (const auto* i = n.as_integer()) return std::to_string(i->get());
    if (const auto* f = n.as_floating_point()) {
      if (!std::isfinite(f->get())) fail(n, key + " is not a finite number");
      return format_number(f->get());
    }
    if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
    fail(n, key + " takes a string, a number or true/false");
  }

  // A table of configuration keys, nested tables read as dotted keys.
  static void flatten(const toml::table& t, const std::string& prefix,
                      std::vector<std::pair<std::string, const toml::node*>>& out) {
    for (const auto& [k, node] : t) {
      const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      if (const auto* sub = node.as_table()) flatten(*sub, key, out);
      else out.emplace_back(key, &node);
    }
  }

  Level level(const toml::table& t, bool top) const {
    Level l;
    for (const auto& [k, node] : t) {
      const std::string key(k.str());
      // One spelling per value: both would leave one of them unused.
      const toml::node& at = node;  // a named copy: clang 14 cannot capture a structured binding
      const auto once = [&](const auto& field, const char* other) {
        if (field) fail(at, key + " and " + other + " both given: give one");
      };
      if (key == "scenes" || key == "scene") {
        once(l.scenes, key == "scene" ? "scenes" : "scene");
        l.scenes = strings(node, key);
      } else if (key == "schemes" || key == "scheme") {
        once(l.schemes, key == "scheme" ? "schemes" : "scheme");
        l.schemes = strings(node, key);
      } else if (key == "resolutions" || key == "resolution") {
        once(l.resolutions, key == "resolution" ? "resolutions" : "resolution");
        l.resolutions = strings(node, key);
        for (const auto& r : *l.resolutions) {
          try {
            (void)parse_frame_resolution(r);
          } catch (const Error& e) {
            fail(node, key + ": " + e.what());
          }
        }
      } else if (key == "frame") l.frame = integers(node, key, 0, 1'000'000);
      else if (key == "frames") l.frames = integers(node, key, 1, 1000);
      else if (key == "aniso") l.aniso = integers(node, key, 1, 16);
      else if (key == "set") {
        const auto* tab = node.as_table();
        if (!tab) fail(node, "set is a table of configuration keys ([set] or set = { key = value })");
        std::vector<std::pair<std::string, const toml::node*>> flat;
        flatten(*tab, "", flat);
        l.set.emplace();
        for (const auto& [name, value_node] : flat) {
          if (value_node->is_array()) fail(*value_node, "set." + name + " is a list: swept values go in [sweep]");
          for (const auto& [other, v] : *l.set)
            if (other == name) fail(*value_node, "set." + name + " is given twice (a dotted key and its table?)");
          if (l.sweep)
            for (const auto& [other, v] : *l.sweep)
              if (other == name) fail(*value_node, name + " is both set and swept: give it in one of [set] and [sweep]");
          l.set->emplace_back(name, value(*value_node, name));
        }
      } else if (key == "sweep") {
        const auto* tab = node.as_table();
        if (!tab) fail(node, "sweep is a table of configuration keys with lists of values");
        std::vector<std::pair<std::string, const toml::node*>> flat;
        flatten(*tab, "", flat);
        l.sweep.emplace();
        for (const auto& [name, list_node] : flat) {
          const auto* a = list_node->as_array();
          if (!a) fail(*list_node, "sweep." + name + " takes a list of values (a single value goes in [set])");
          if (a->empty()) fail(*list_node, "sweep." + name + " is an empty list");
          for (const auto& [other, v] : *l.sweep)
            if (other == name) fail(*list_node, "sweep." + name + " is given twice (a dotted key and its table?)");
          if (l.set)
            for (const auto& [other, v] : *l.set)
              if (other == name) fail(*list_node, name + " is both set and swept: give it in one of [set] and [sweep]");
          std::vector<std::string> values;
          for (const auto& x : *a) values.push_back(value(x, name));
          l.sweep->emplace_back(name, values);
        }
      } else if (top && (key == "name" || key == "config" || key == "description" || key == "images" || key == "point")) {
        continue;  // read by read_top
      } else {
        fail(node, "unknown key '" + key + "' (" +
                       (top ? "name, description, config, images, scenes, schemes, resolutions, frame, frames, aniso, [set], "
                              "[sweep], [[point]]"
                            : "a point takes scene, scheme, resolution, frame, frames, aniso, set, sweep") +
                       ")");
      }
    }
    return l;
  }

 private:
  std::string m_file;
};

// `point` with what it leaves out taken from `top`.
Level inherit(const Level& top, Level point) {
  if (!point.scenes) point.scenes = top.scenes;
  if (!point.schemes) point.schemes = top.schemes;
  if (!point.resolutions) point.resolutions = top.resolutions;
  if (!point.frame) point.frame = top.frame;
  if (!point.frames) point.frames = top.frames;
  if (!point.aniso) point.aniso = top.aniso;
  if (!point.sweep) point.sweep = top.sweep;
  // A point's settings add to the file's (its own win).
  std::vector<std::pair<std::string, std::string>> set = top.set.value_or(decltype(set){});
  if (point.set) set.insert(set.end(), point.set->begin(), point.set->end());
  point.set = set;
  return point;
}

// The cross product of a level, schemes innermost (points sharing traces
// follow each other).
void expand(const Level& l, const std::string& where, std::vector<SweepPoint>& out, const Reader& reader, uint64_t& bytes) {
  if (!l.scenes) reader.fail(where + " names no scene (scenes = [...])");
  if (!l.schemes) reader.fail(where + " names no scheme (schemes = [...])");
  const std::vector<std::string> resolutions = l.resolutions.value_or(std::vector<std::string>{"1280x1024"});
  const std::vector<int> frame = l.frame.value_or(std::vector<int>{0});
  const std::vector<int> frames = l.frames.value_or(std::vector<int>{0});
  const std::vector<int> aniso = l.aniso.value_or(std::vector<int>{16});
  const auto& sweep = *l.sweep;
  // Counted saturating, so that long lists cannot wrap the product around.
  size_t count = 1;
  const auto times = [&](size_t n) { count = count > kMaxPoints / std::max<size_t>(n, 1) ? kMaxPoints + 1 : count * n; };
  for (size_t n : {l.scenes->size(), l.schemes->size(), resolutions.size(), frame.size(), frames.size(), aniso.size()}) times(n);
  for (const auto& [key, values] : sweep) times(values.size());
  if (count + out.size() > kMaxPoints)
    reader.fail(where + " makes more than " + std::to_string(kMaxPoints) + " points: split the sweep");
  // What the points will hold, counted before they are made: their names
  // and settings, and a resolved configuration each (kPointBytes).
  uint64_t scene_chars = 0, scheme_chars = 0;
  for (const auto& x : *l.scenes) scene_chars = std::max<uint64_t>(scene_chars, x.size());
  for (const auto& x : *l.schemes) scheme_chars = std::max<uint64_t>(scheme_chars, x.size());
  const uint64_t names = 2 * scene_chars + scheme_chars;  // the scene is in the point and its trace group
  uint64_t settings = 0;
  for (const auto& [key, value] : *l.set) settings += key.size() + value.size() + 64;
  for (const auto& [key, values] : sweep) {
    uint64_t longest = 0;
    for (const auto& v : values) longest = std::max<uint64_t>(longest, v.size());
    settings += 2 * (key.size() + longest + 64);  // in settings and in swept
  }
  bytes += count * (kPointBytes + names + settings);
  if (bytes > kMaxPointsBytes)
    reader.fail(where + " makes points that would hold about " + std::to_string(bytes >> 20) + " MB (more than " +
                std::to_string(kMaxPointsBytes >> 20) + " MB): split the sweep, or shorten its names and settings");
  std::vector<size_t> index(sweep.size(), 0);  // the swept keys' odometer
  for (const auto& scene : *l.scenes)
    for (const auto& res : resolutions)
      for (int f : frame)
        for (int n : frames)
          for (int a : aniso) {
            std::fill(index.begin(), index.end(), 0);
            for (;;) {
              for (const auto& scheme : *l.schemes) {
                SweepPoint p;
                p.scene = scene;
                p.scheme = scheme;
                p.resolution = res;
                p.frame = f;
                p.frames = n;
                p.aniso = a;
                p.settings = *l.set;
                for (size_t k = 0; k < sweep.size(); ++k) {
                  p.settings.emplace_back(sweep[k].first, sweep[k].second[index[k]]);
                  p.swept[sweep[k].first] = sweep[k].second[index[k]];
                }
                out.push_back(std::move(p));
              }
              size_t k = sweep.size();
              while (k > 0 && ++index[k - 1] == sweep[k - 1].second.size()) index[--k] = 0;
              if (k == 0) break;
            }
          }
}

std::string describe(const SweepPoint& p) {
  std::string s = p.scene + ", " + p.scheme + ", " + p.resolution;
  for (const auto& [k, v] : p.swept) s += ", " + k + "=" + v;
  return s;
}

// A sweep file's TOML, checked first (check_toml_text); Error naming the
// line on a syntax error.
toml::table parse_toml(const std::string& text, const std::string& name) {
  check_toml_text(text, name);
  try {
    return toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw Error("bad sweep '" + name + "' line " + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
  }
}

// The machine preset a sweep's `config` names (relative to the file's
// folder `base_dir`), "" when it names none.
std::string preset_of(const toml::table& t, const Reader& reader, const std::string& base_dir) {
  const auto* n = t.get("config");
  if (!n) return "";
  if (!n->as_string() || n->as_string()->get().empty()) reader.fail(*n, "config takes the path of a machine preset");
  const fs::path p = n->as_string()->get();
  return (p.is_relative() && !base_dir.empty() ? fs::path(base_dir) / p : p).lexically_normal().string();
}

// --set's "key=value" as (key, value); Error without a key or '='.
std::pair<std::string, std::string> split_setting(const std::string& setting) {
  const size_t eq = setting.find('=');
  if (eq == std::string::npos || eq == 0)
    throw Error("--set " + printable(setting) + ": give key=value (e.g. --set link.bandwidth=32GBps)");
  return {setting.substr(0, eq), setting.substr(eq + 1)};
}

}  // namespace

std::string canonical_point(const std::string& scene, const std::string& scheme, const std::string& resolution, int frame,
                            int frames, int aniso, const nlohmann::ordered_json& config) {
  nlohmann::ordered_json j;
  j["scene"] = scene;
  j["scheme"] = scheme;
  j["resolution"] = resolution;
  j["frame"] = frame;
  j["frames"] = frames;
  j["aniso"] = aniso;
  j["config"] = config;
  return j.dump();
}

bool is_sweep_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name.front() == '.' || name.front() == '-') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
  });
}

std::string stable_id(const std::string& text) {
  uint64_t h = 14695981039346656037ull;  // FNV-1a 64: offset basis and prime
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  static const char* hex = "0123456789abcdef";
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i, h >>= 4) out[size_t(i)] = hex[h & 15];
  return out;
}

Sweep parse_sweep(const std::string& text, const std::string& name, const std::string& base_dir) {
  const toml::table t = parse_toml(text, name);
  const Reader reader(name);
  Sweep s;
  s.file = name;
  s.definition = text;
  s.name = fs::path(name).stem().string();
  if (const auto* n = t.get("name")) {
    if (!n->as_string() || n->as_string()->get().empty()) reader.fail(*n, "name takes a non-empty string");
    s.name = n->as_string()->get();
    if (!is_sweep_name(s.name))
      reader.fail(*n, "name '" + printable(s.name) + "' is not a sweep name: 1 to 64 letters, digits, '_', '-' and '.'");
  } else if (!is_sweep_name(s.name)) {
    reader.fail("the sweep has no name, and its file's name '" + printable(s.name) +
                "' is not one: give name = \"...\" (1 to 64 letters, digits, '_', '-' and '.')");
  }
  if (const auto* n = t.get("description"); n && !n->as_string()) reader.fail(*n, "description takes a string");
  s.preset = preset_of(t, reader, base_dir);
  if (const auto* n = t.get("images")) {
    if (!n->as_boolean()) reader.fail(*n, "images takes true or false");
    s.images = n->as_boolean()->get();
  }
  const Level top = reader.level(t, true);
  if (top.set) s.base_settings = *top.set;
  // The columns: every key swept anywhere in the file.
  std::set<std::string> seen;
  const auto add_columns = [&](const Level& l) {
    if (l.sweep)
      for (const auto& [key, values] : *l.sweep)
        if (seen.insert(key).second) s.swept_keys.push_back(key);
  };
  add_columns(top);
  Level top_full = top;
  if (!top_full.sweep) top_full.sweep.emplace();
  if (!top_full.set) top_full.set.emplace();
  // The grid of the top level, when it names schemes.
  uint64_t bytes = 0;
  if (top.schemes) expand(top_full, "the file's top level", s.points, reader, bytes);
  if (const auto* points = t.get("point")) {
    const auto* a = points->as_array();
    if (!a || !a->is_array_of_tables()) reader.fail(*points, "point entries are tables ([[point]])");
    for (size_t i = 0; i < a->size(); ++i) {
      const Level p = reader.level(*a->get(i)->as_table(), false);
      add_columns(p);
      expand(inherit(top_full, p), "point " + std::to_string(i + 1), s.points, reader, bytes);
    }
  }
  if (s.points.empty()) reader.fail("no points: give schemes = [...] (and scenes) at the top level, or [[point]] tables");
  return s;
}

namespace {

// JSON values as TOML, written into their parent (a table under `key`, or
// an array); `where` names the value for errors.
template <class Put>
void toml_of(const nlohmann::json& j, const std::string& where, int depth, Put put);

void fill_table(toml::table& t, const nlohmann::json& j, const std::string& where, int depth) {
  for (const auto& item : j.items()) {
    const std::string key = item.key();  // a named copy: clang 14 cannot capture a structured binding
    toml_of(item.value(), where + "." + key, depth + 1, [&](auto&& x) { t.insert_or_assign(key, std::forward<decltype(x)>(x)); });
  }
}

void fill_array(toml::array& a, const nlohmann::json& j, const std::string& where, int depth) {
  for (size_t i = 0; i < j.size(); ++i)
    toml_of(j[i], where + "[" + std::to_string(i) + "]", depth + 1, [&](auto&& x) { a.push_back(std::forward<decltype(x)>(x)); });
}

template <class Put>
void toml_of(const nlohmann::json& j, const std::string& where, int depth, Put put) {
  if (depth > 64) throw Error("sweep definition: " + where + " nests too deep");
  switch (j.type()) {
    case nlohmann::json::value_t::object: {
      toml::table t;
      fill_table(t, j, where, depth);
      put(std::move(t));
      return;
    }
    case nlohmann::json::value_t::array: {
      toml::array a;
      fill_array(a, j, where, depth);
      put(std::move(a));
      return;
    }
    case nlohmann::json::value_t::string: put(j.get<std::string>()); return;
    case nlohmann::json::value_t::boolean: put(j.get<bool>()); return;
    case nlohmann::json::value_t::number_unsigned:
      if (j.get<uint64_t>() > uint64_t(INT64_MAX)) throw Error("sweep definition: " + where + " is too large");
      put(j.get<int64_t>());
      return;
    case nlohmann::json::value_t::number_integer: put(j.get<int64_t>()); return;
    case nlohmann::json::value_t::number_float: put(j.get<double>()); return;
    default: throw Error("sweep definition: " + where + " is " + std::string(j.type_name()) + ", which a sweep file cannot hold");
  }
}

}  // namespace

std::string sweep_toml(const nlohmann::json& definition) {
  if (!definition.is_object())
    throw Error("a sweep definition is a table of keys (a dict), not " + std::string(definition.type_name()));
  toml::table t;
  fill_table(t, definition, "sweep", 0);
  std::ostringstream out;
  out << t << "\n";
  return out.str();
}

Sweep read_sweep(const std::string& path, const std::vector<std::string>& settings) {
  const std::string text = read_input_file(path, "sweep", uint64_t(1) << 20);
  return parse_sweep(settings.empty() ? text : sweep_with_settings(text, path, settings), path,
                     fs::path(path).parent_path().string());
}

std::string sweep_with_settings(const std::string& text, const std::string& name, const std::vector<std::string>& settings) {
  toml::table t = parse_toml(text, name);
  // The keys the file varies: its [sweep], and every point's set and sweep.
  const auto keys_of = [](const toml::node* node, std::vector<std::string>& out) {
    if (const auto* tab = node ? node->as_table() : nullptr) {
      std::vector<std::pair<std::string, const toml::node*>> flat;
      Reader::flatten(*tab, "", flat);
      for (const auto& [key, v] : flat) out.push_back(key);
    }
  };
  std::vector<std::string> swept, point_set;
  keys_of(t.get("sweep"), swept);
  if (const auto* points = t.get("point"); points && points->as_array())
    for (const auto& p : *points->as_array())
      if (const auto* pt = p.as_table()) {
        keys_of(pt->get("sweep"), swept);
        keys_of(pt->get("set"), point_set);
      }
  toml::node* top_set = t.get("set");
  if (top_set && !top_set->as_table())
    throw Error("bad sweep '" + name + "': set is a table of configuration keys ([set] or set = { key = value })");
  std::string given;
  for (const std::string& s : settings) {
    const auto [key, value] = split_setting(s);
    if (std::find(swept.begin(), swept.end(), key) != swept.end())
      throw Error("--set " + printable(key) + ": the sweep '" + name + "' sweeps it; edit the file to change its values");
    if (std::find(point_set.begin(), point_set.end(), key) != point_set.end())
      throw Error("--set " + printable(key) + ": a point of the sweep '" + name + "' sets it; edit the file to change it");
    if (!top_set) top_set = t.insert_or_assign("set", toml::table{}).first->second.as_table();
    toml::table& set = *top_set->as_table();
    // The file's own spelling of the key, dotted or nested, gives way.
    set.erase(key);
    toml::table* parent = &set;
    size_t from = 0;
    for (size_t dot = key.find('.'); dot != std::string::npos && parent; dot = key.find('.', from = dot + 1)) {
      toml::node* child = parent->get(key.substr(from, dot - from));
      parent = child ? child->as_table() : nullptr;
      if (parent) parent->erase(key.substr(dot + 1));
    }
    set.insert_or_assign(key, value);
    given += " --set " + s;
  }
  std::ostringstream out;
  // One comment line: printable() keeps a new line in a name or a value
  // from ending it (and what follows from being read as TOML).
  out << "# " << printable(name + " with" + given) << "\n" << t << "\n";
  return out.str();
}

namespace {

// "oo-app, oo-vr": the registered schemes that read `section`.
std::string schemes_reading(const std::string& section) {
  std::string out;
  for (const auto& name : schemes_in_order()) {
    const auto& own = Schemes::find(name)->sections;
    if (std::find(own.begin(), own.end(), section) != own.end()) out += (out.empty() ? "" : ", ") + name;
  }
  return out.empty() ? "none registered" : out;
}

}  // namespace

void resolve(SweepPoint& p, const Config& machine) {
  try {
    Config c = machine;
    c.set_source("sweep");
    for (const auto& [key, value] : p.settings) c.set(key, value);
    MachineSpec machine_spec = MachineSpec::from_config(c);  // every key read, once
    const StereoRig rig = parse_frame_resolution(p.resolution);
    p.window = measured_window({p.scheme}, machine_spec, p.frames, "frames");
    // A point's setting its scheme does not read would make points that
    // differ only in it the same run.
    for (const auto& [key, value] : p.settings)
      if (!scheme_reads_key(p.scheme, key))
        throw Error("'" + key + "' is a setting of the schemes with the '" + config_section_of(key) + "' section (" +
                    schemes_reading(config_section_of(key)) + "), not of " + p.scheme + ": give it in their points only");
    // Its id hashes the keys its run reads: the machine's and its scheme's
    // own (a scheme added with keys of its own changes no point's id).
    nlohmann::ordered_json config = nlohmann::ordered_json::object();
    for (const auto& [key, e] : scheme_entries(p.scheme, machine_spec.entries)) config[key] = base_value(e);
    p.canonical = canonical_point(p.scene, p.scheme, std::to_string(rig.frame_width()) + "x" + std::to_string(rig.frame_height()),
                                  p.frame, p.window, p.aniso, config);
    p.id = stable_id(p.canonical);
    p.machine = std::move(machine_spec);
  } catch (const UnknownKeyError& e) {  // the kind kept, for the Python module's KeyError
    throw UnknownKeyError("point (" + describe(p) + "): " + e.what());
  } catch (const NotFoundError& e) {
    throw NotFoundError("point (" + describe(p) + "): " + e.what());
  } catch (const Error& e) {
    throw Error("point (" + describe(p) + "): " + e.what());
  }
}

namespace {

// Leaves out of s.points each point that is the same run as an earlier one
// (resolve_all).
void share_identical_points(Sweep& s) {
  std::map<std::string, size_t> first;  // id -> its place in `kept`
  std::vector<SweepPoint> kept;
  kept.reserve(s.points.size());
  for (size_t i = 0; i < s.points.size(); ++i) {
    SweepPoint& p = s.points[i];
    const auto [it, fresh] = first.emplace(p.id, kept.size());
    if (fresh) {
      kept.push_back(std::move(p));
      continue;
    }
    SweepPoint& earlier = kept[it->second];
    for (const auto& [key, value] : p.swept) earlier.swept.emplace(key, value);
    s.shared.push_back("point " + std::to_string(i + 1) + " (" + describe(p) + ") is the same run as an earlier point (" +
                       describe(earlier) + "; id " + p.id + "): run once");
  }
  s.points = std::move(kept);
}

}  // namespace

Config resolve_all(Sweep& s) {
  const Config machine = s.preset.empty() ? Config{} : Config::from_toml_file(s.preset);
  for (SweepPoint& p : s.points) resolve(p, machine);
  share_identical_points(s);
  return machine;
}

std::string sweep_on_machine(const std::string& text, const std::string& name, const std::string& base_dir,
                             const std::string& preset, const std::vector<std::string>& settings, int frames,
                             std::map<std::string, std::string>* sources) {
  toml::table t = parse_toml(text, name);
  const Reader reader(name);
  struct Given {
    std::string key, value, source;
  };
  std::vector<Given> given;
  std::string how;  // for the text's first line
  const std::string from = preset.empty() ? preset_of(t, reader, base_dir) : preset;
  if (!from.empty()) {
    for (const Config::Setting& x : Config::from_toml_file(from).settings()) given.push_back({x.key, x.text, x.source});
    how += " --config " + from;
  }
  toml::node* top_set = t.get("set");
  if (top_set && !top_set->as_table())
    reader.fail(*top_set, "set is a table of configuration keys ([set] or set = { key = value })");
  if (top_set) {
    std::vector<std::pair<std::string, const toml::node*>> flat;
    Reader::flatten(*top_set->as_table(), "", flat);
    for (const auto& [key, node] : flat) given.push_back({key, reader.value(*node, key), name + " [set]"});
  }
  for (const std::string& x : settings) {
    const auto [key, value] = split_setting(x);
    given.push_back({key, value, "--set"});
    how += " --set " + x;
  }
  if (frames != 0) {
    if (frames < 1 || frames > 1000) throw Error("--frames " + std::to_string(frames) + " is outside 1 to 1000");
    if (const auto* points = t.get("point"); points && points->as_array())
      for (const auto& p : *points->as_array())
        if (const auto* pt = p.as_table(); pt && pt->get("frames"))
          throw Error("--frames: a point of the sweep '" + name + "' sets its own frames; edit the file to change them");
    t.insert_or_assign("frames", int64_t(frames));
    how += " --frames " + std::to_string(frames);
  }
  if (given.empty() && frames == 0) return text;
  // Checked as a configuration first: a bad key or value is named with
  // where it came from, not as a line of the rewritten text.
  Config check;
  for (const Given& g : given) {
    check.set_source(g.source);
    check.set(g.key, g.value);
  }
  check_config(check);
  t.erase("config");
  std::map<std::string, std::string> where;
  if (!given.empty()) {
    toml::table set;
    for (const Given& g : given) {
      set.insert_or_assign(g.key, g.value);
      where[g.key] = g.source;
    }
    t.insert_or_assign("set", std::move(set));
  }
  if (sources) *sources = where;
  std::ostringstream out;
  out << "# "
      << printable(name + (how.empty() ? " with its [set] as the machine" : " with" + how) +
                   (given.empty() ? "" : ": every key of the machine its points run on is in [set]"))
      << "\n"
      << t << "\n";
  return out.str();
}

Config sweep_machine(const Sweep& s, const std::map<std::string, std::string>& sources) {
  Config machine = s.preset.empty() ? Config{} : Config::from_toml_file(s.preset);
  for (const auto& [key, value] : s.base_settings) {
    const auto it = sources.find(key);
    machine.set_source(it != sources.end() ? it->second : s.file + " [set]");
    machine.set(key, value);
  }
  machine.set_source("--set");
  Config probe = machine;  // checked on a copy: the machine's entries stay those its readers record
  check_config(probe);
  return machine;
}

Config resolve_on_machine(Sweep& s, const std::map<std::string, std::string>& sources) {
  const Config machine = sweep_machine(s, sources);
  const size_t n = s.base_settings.size();
  for (SweepPoint& p : s.points) {
    if (p.settings.size() < n || !std::equal(s.base_settings.begin(), s.base_settings.end(), p.settings.begin()))
      throw Error("bad sweep '" + s.file + "': point (" + describe(p) + ") does not start from the file's [set]");
    p.settings.erase(p.settings.begin(), p.settings.begin() + std::ptrdiff_t(n));
    resolve(p, machine);
  }
  share_identical_points(s);
  return machine;
}

std::string trace_group(const SweepPoint& p) {
  return p.scene + "|" + p.resolution + "|" + std::to_string(p.frame) + "|" + std::to_string(p.aniso) + "|" +
         std::to_string(p.machine.memory.line.value);
}

}  // namespace oovr
