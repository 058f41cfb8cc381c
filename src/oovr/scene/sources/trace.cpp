// Captured game frames as scene sources (scene/formats/gl_trace.h):
//
//   trace:PATH[?frames=A-B]   any apitrace capture of an OpenGL game
//                              oovr's interpreter reads (fixed-function
//                              OpenGL 1.x, DarkPlaces' or ioquake3's GLSL
//                              renderer);
//                              frames A to B (default 0-63)
//   oa-demo:NAME[?frames=A-B] a demo OpenArena ships, captured by
//                              scripts/capture-frames.sh into oovr's
//                              capture folder; frames as the script chose
//                              them unless given
//   nexuiz-demo:NAME[?frames=A-B] the same for a demo Nexuiz ships
//
// The camera path is the capture's frames: frame k of the scene is frame
// A + k of the game.
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"
#include "oovr/core/version.h"
#include "oovr/scene/formats/gl_trace.h"
#include "oovr/scene/scene_codec.h"
#include "oovr/scene/source.h"

namespace oovr {
namespace {

namespace fs = std::filesystem;

// The most frames one scene imports: each holds about 400 draws of a
// game, about 18 KB each in the simulator.
constexpr int kMaxWindow = 4096;

// "A-B" (inclusive) into a window; Error naming the spec otherwise.
GlTraceWindow parse_frames(const std::string& text, const std::string& spec) {
  const auto dash = text.find('-');
  std::optional<uint64_t> a, b;
  if (dash != std::string::npos) {
    a = parse_whole_number(text.substr(0, dash), 0, 100000000);
    b = parse_whole_number(text.substr(dash + 1), 0, 100000000);
  }
  if (!a || !b || *b < *a)
    throw Error("scene option 'frames' in '" + spec + "' must be A-B, the first and last frame (A <= B), not '" + text + "'");
  if (*b - *a + 1 > uint64_t(kMaxWindow))
    throw Error("scene option 'frames' in '" + spec + "' asks for " + std::to_string(*b - *a + 1) + " frames; at most " +
                std::to_string(kMaxWindow) + " are imported at once");
  GlTraceWindow w;
  w.first = int(*a);
  w.count = int(*b - *a + 1);
  return w;
}

GlTraceWindow window_option(const SceneOptions& options, const std::string& spec, GlTraceWindow fallback) {
  for (const auto& [k, v] : options) {
    if (k == "frames") return parse_frames(v, spec);
    unknown_scene_option(k, spec, "frames=A-B");
  }
  return fallback;
}

// What decides an import: the capture (its absolute path, size and
// modification time), the window and the code (oovr's commit). Empty where
// the code is not a commit (a build of an edited tree), whose imports are
// not cached: its interpreter may differ from the commit's.
std::string import_key(const std::string& path, const GlTraceWindow& w) {
  const std::string commit = git_commit();
  if (commit == "unknown" || commit.find("-dirty") != std::string::npos) return "";
  std::error_code ec;
  const fs::path abs = fs::absolute(path, ec);
  const auto size = fs::file_size(path, ec);
  if (ec) return "";
  const auto mtime = fs::last_write_time(path, ec).time_since_epoch().count();
  if (ec) return "";
  return std::string("import\n") + abs.string() + "\n" + std::to_string(size) + "\n" + std::to_string(mtime) + "\n" +
         std::to_string(w.first) + "-" + std::to_string(w.count) + "\n" + std::to_string(w.metres_per_unit) + "\n" + commit;
}

// Imports a window of a capture, from the cache of imports when it is there
// (docs/real-frames.md); a cached scene that does not verify is imported
// again.
Scene load_trace(const std::string& spec, const std::string& path, const GlTraceWindow& w) {
  const std::string key = import_key(path, w);
  const SceneCache cache;
  if (!key.empty())
    if (auto cached = cache.load(key)) {
      cached->name = spec;
      return std::move(*cached);
    }
  Scene s = import_gl_trace(path, w);
  if (!key.empty()) cache.store(key, s);
  s.name = spec;
  return s;
}

// Where scripts/capture-frames.sh keeps its captures.
std::string capture_directory() {
  if (const char* d = std::getenv("OOVR_CAPTURE_DIR"); d && *d) return d;
  return user_cache_folder("captures");
}

// A capture's files: NAME.trace and NAME.frames ("A-B", the window the
// script chose).
std::string capture_path(const std::string& game, const std::string& name, const char* ext) {
  return capture_directory() + "/" + game + "-" + name + ext;
}

bool valid_capture_name(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) return false;
  return true;
}

std::vector<SceneListing> list_captures(const std::string& game, const std::string& prefix, const std::string& what) {
  std::vector<SceneListing> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(capture_directory(), ec)) {
    const std::string file = e.path().filename().string();
    const std::string head = game + "-";
    if (file.size() <= head.size() + 6 || file.compare(0, head.size(), head) != 0 || e.path().extension() != ".trace") continue;
    const std::string name = file.substr(head.size(), file.size() - head.size() - 6);
    if (valid_capture_name(name)) out.push_back({prefix + ":" + name, what, "captured with scripts/capture-frames.sh"});
  }
  std::sort(out.begin(), out.end(), [](const SceneListing& a, const SceneListing& b) { return a.name < b.name; });
  return out;
}

Scene load_capture(const std::string& game, const std::string& spec, const std::string& name, const SceneOptions& options) {
  if (!valid_capture_name(name))
    throw Error("'" + printable(spec) + "': a capture's name is 1 to 64 letters, digits, '-' and '_'");
  const std::string trace = capture_path(game, name, ".trace");
  std::error_code ec;
  if (!fs::exists(trace, ec))
    throw Error("'" + spec + "' is not captured: run scripts/capture-frames.sh " + game + " (it records the demo into " +
                capture_directory() + ")");
  std::string frames = read_input_file(capture_path(game, name, ".frames"), "capture window", 64);
  while (!frames.empty() && (frames.back() == '\n' || frames.back() == ' ')) frames.pop_back();
  const GlTraceWindow w = window_option(options, spec, parse_frames(frames, capture_path(game, name, ".frames")));
  return load_trace(spec, trace, w);
}

const SceneSources::Add trace_reg("trace", {"apitrace capture", "trace:PATH[?frames=A-B]", true, 0,
                                            [] { return std::vector<SceneListing>{}; }, nullptr,
                                            [](const std::string& spec, const std::string& path, const SceneOptions& options) {
                                              GlTraceWindow first;
                                              first.count = 64;
                                              return load_trace(spec, path, window_option(options, spec, first));
                                            },
                                            nullptr});

const SceneSources::Add oa_reg("oa-demo", {"openarena demo", "oa-demo:NAME[?frames=A-B]", true, 0,
                                           [] { return list_captures("openarena", "oa-demo", "openarena demo"); }, nullptr,
                                           [](const std::string& spec, const std::string& name, const SceneOptions& options) {
                                             return load_capture("openarena", spec, name, options);
                                           },
                                           capture_directory});

const SceneSources::Add nexuiz_reg("nexuiz-demo",
                                   {"nexuiz demo", "nexuiz-demo:NAME[?frames=A-B]", true, 0,
                                    [] { return list_captures("nexuiz", "nexuiz-demo", "nexuiz demo"); }, nullptr,
                                    [](const std::string& spec, const std::string& name, const SceneOptions& options) {
                                      return load_capture("nexuiz", spec, name, options);
                                    },
                                    capture_directory});

}  // namespace
}  // namespace oovr
