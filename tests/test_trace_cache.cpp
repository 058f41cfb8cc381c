// The trace cache: a hit is the trace that was stored, and anything else
// under a key (a flipped byte anywhere, a trace of another scene, a crafted
// header, a FIFO, a directory, a link to a device) is a miss that is
// reported once, rendered again and replaced, with the results of an
// uncached run.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "oovr/core/config.h"
#include "oovr/core/error.h"
#include "oovr/pipeline/trace_cache.h"
#include "oovr/pipeline/trace_format.h"
#include "oovr/run/frames.h"
#include "oovr/run/session.h"
#include "oovr/scene/builtin.h"
#include "oovr/schemes/i_scheme.h"
#include "temp_dir.h"

namespace oovr {
namespace {

namespace fs = std::filesystem;

struct Rendered {
  Scene scene;
  StereoView view;
  PipelineSettings settings;
  FrameOutput out;
};

Rendered render_builtin(const std::string& name, int frame, int eye_w = 96, int eye_h = 64) {
  Rendered r{BuiltinScenes::find(name)->make(), {}, {}, {}};
  StereoRig rig;
  rig.eye_width = eye_w;
  rig.eye_height = eye_h;
  r.view = make_stereo_view(r.scene.camera, frame, rig);
  r.out = render_frame(r.scene, r.view, r.settings, frame);
  return r;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_file(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

// Points the cache every load_window uses at a test's own folder.
class CacheDirectory {
 public:
  explicit CacheDirectory(const fs::path& p) {
    if (const char* old = std::getenv("OOVR_CACHE_DIR")) m_old = old;
    ::setenv("OOVR_CACHE_DIR", p.c_str(), 1);
  }
  ~CacheDirectory() {
    if (m_old.empty()) ::unsetenv("OOVR_CACHE_DIR");
    else ::setenv("OOVR_CACHE_DIR", m_old.c_str(), 1);
  }

 private:
  std::string m_old;
};

TEST(TraceCache, PayloadRoundTripsAndRefusesWhatTheRendererCannotWrite) {
  const Rendered r = render_builtin("crowd", 7);
  const std::string bytes = serialize_trace(r.out.trace);
  const auto back = deserialize_trace(bytes);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->tiles, r.out.trace.tiles);
  EXPECT_EQ(back->objects, r.out.trace.objects);
  EXPECT_EQ(back->tex_lines, r.out.trace.tex_lines);
  EXPECT_EQ(back->tiles_x, r.out.trace.tiles_x);
  EXPECT_FALSE(deserialize_trace(bytes.substr(0, bytes.size() / 2)).has_value()) << "truncated";
  EXPECT_FALSE(deserialize_trace(bytes + "x").has_value()) << "trailing bytes";
  // Each of these once divided by zero, indexed out of range or looped.
  const auto refused = [&](auto change) {
    FrameTrace t = r.out.trace;
    change(t);
    return !deserialize_trace(serialize_trace(t)).has_value();
  };
  EXPECT_TRUE(refused([](FrameTrace& t) { t.block_w = 0; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.block_h = 3; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.tile_size = 0; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.tiles_x += 1; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.line_bytes = 96; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.frame_width = -4; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.texture_format = TextureFormat(9); }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.tiles.back().object = uint32_t(t.objects.size()); }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.tiles.back().eye = 2; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.tiles.back().tile_y = uint16_t(t.tiles_y); }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.tiles.back().tex_begin = ~uint64_t(0) - 2; }));
  EXPECT_TRUE(refused([](FrameTrace& t) { t.tiles.back().tex_count = uint32_t(t.tex_lines.size() + 1); }));
  EXPECT_TRUE(refused([](FrameTrace& t) { std::swap(t.tiles.front(), t.tiles.back()); }));
  EXPECT_FALSE(refused([](FrameTrace&) {})) << "the unchanged trace";
}

TEST(TraceCache, EntriesCarryTheirKeyAndAChecksum) {
  const Rendered r = render_builtin("crowd", 7);
  const std::string entry = encode_entry("0123456789abcdef", r.out.trace);
  std::string why;
  ASSERT_TRUE(decode_entry(entry, "0123456789abcdef", &why).has_value()) << why;
  EXPECT_FALSE(decode_entry(entry, "0123456789abcdee", &why).has_value());
  EXPECT_EQ(why, "stored under another key");
  std::string bad = entry;
  bad[bad.size() - 5] ^= 0x10;
  EXPECT_FALSE(decode_entry(bad, "0123456789abcdef", &why).has_value());
  EXPECT_EQ(why, "checksum mismatch");
  // A trace with a header no renderer writes, under the right key and with
  // the right checksum (a crafted file), is still refused.
  FrameTrace t = r.out.trace;
  t.block_w = 0;
  EXPECT_FALSE(decode_entry(encode_entry("k", t), "k", &why).has_value());
  EXPECT_EQ(why, "inconsistent trace");
}

TEST(TraceCache, KeysFollowEverythingThatDecidesATrace) {
  const test::TempDir dir;
  const TraceCache cache(dir.path().string());
  const Scene s = BuiltinScenes::find("crowd")->make();
  StereoRig rig;
  rig.eye_width = 64;
  rig.eye_height = 64;
  const StereoView v0 = make_stereo_view(s.camera, 0, rig), v1 = make_stereo_view(s.camera, 1, rig);
  PipelineSettings p, q;
  q.max_anisotropy = 4;
  const uint64_t f = scene_fingerprint(s);
  const std::string k = cache.key(f, 0, v0, p);
  EXPECT_EQ(k, cache.key(scene_fingerprint(BuiltinScenes::find("crowd")->make()), 0, v0, p)) << "deterministic";
  EXPECT_NE(k, cache.key(f, 1, v1, p));
  EXPECT_NE(k, cache.key(f, 0, v0, q));
  EXPECT_NE(k, cache.key(f + 1, 0, v0, p));
  EXPECT_NE(k, cache.key(f, 0, v0, p, kPipelineVersion + 1)) << "a renderer change (version.h)";
  StereoView offset = v0;  // the same matrices, other eye offsets: captured draws re-project by them
  offset.eye_offset_m[0] = -0.04f;
  offset.eye_offset_m[1] = 0.04f;
  EXPECT_NE(k, cache.key(f, 0, offset, p)) << "eye offsets";
  EXPECT_FALSE(cache.load(k, s, 0, v0, p).trace.has_value());
  EXPECT_EQ(cache.load(k, s, 0, v0, p).rejected, "") << "no entry is not a rejected entry";
  const FrameOutput out = render_frame(s, v0, p);
  EXPECT_TRUE(cache.store(k, out.trace));
  const auto hit = cache.load(k, s, 0, v0, p);
  ASSERT_TRUE(hit.trace.has_value()) << hit.rejected;
  EXPECT_EQ(hit.trace->tiles, out.trace.tiles);
  // The same entry asked for as another frame, view or scene is refused.
  EXPECT_NE(cache.load(k, s, 1, v0, p).rejected, "");
  ASSERT_TRUE(cache.store(k, out.trace));
  StereoRig wide = rig;
  wide.eye_width = 80;
  EXPECT_NE(cache.load(k, s, 0, make_stereo_view(s.camera, 0, wide), p).rejected, "") << "a frame of another size";
  ASSERT_TRUE(cache.store(k, out.trace));
  const Scene other = BuiltinScenes::find("courtyard")->make();
  EXPECT_NE(cache.load(k, other, 0, v0, p).rejected, "") << "a trace of another scene";
}

TEST(TraceCache, DropsTheLeastRecentlyUsedTracesWhenFull) {
  const test::TempDir dir;
  TraceCache cache(dir.path().string());
  const Rendered r = render_builtin("crowd", 0);
  const uint64_t one = encode_entry("a", r.out.trace).size();
  cache.set_max_bytes(2 * one + one / 2);  // room for two traces
  ASSERT_TRUE(cache.store("a", r.out.trace));
  ASSERT_TRUE(cache.store("b", r.out.trace));
  // Make "a" the older file, then use it: "b" becomes the least recent.
  const auto past = fs::file_time_type::clock::now() - std::chrono::hours(2);
  fs::last_write_time(dir.path() / "a.trace", past);
  fs::last_write_time(dir.path() / "b.trace", past + std::chrono::hours(1));
  ASSERT_TRUE(cache.load("a", r.scene, 0, r.view, r.settings).trace.has_value());
  ASSERT_TRUE(cache.store("c", r.out.trace));
  EXPECT_TRUE(fs::exists(dir.path() / "a.trace"));
  EXPECT_FALSE(fs::exists(dir.path() / "b.trace"));
  EXPECT_TRUE(fs::exists(dir.path() / "c.trace"));
  // A trace larger than the whole cache is not stored, and a file larger
  // than the cache is not read.
  cache.set_max_bytes(one - 1);
  EXPECT_FALSE(cache.store("d", r.out.trace));
  EXPECT_FALSE(fs::exists(dir.path() / "d.trace"));
  const auto big = cache.load("a", r.scene, 0, r.view, r.settings);
  EXPECT_FALSE(big.trace.has_value());
  EXPECT_NE(big.rejected.find("larger than the cache"), std::string::npos) << big.rejected;
}

TEST(TraceCache, OnlyRegularFilesAreRead) {
  const test::TempDir dir;
  const TraceCache cache(dir.path().string());
  const Rendered r = render_builtin("crowd", 0);
  const auto load = [&] { return cache.load("k", r.scene, 0, r.view, r.settings); };
  const fs::path path = dir.path() / "k.trace";
  // A FIFO would block a reader for ever; /dev/zero would fill its memory.
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  auto got = load();
  EXPECT_FALSE(got.trace.has_value());
  EXPECT_NE(got.rejected.find("not a regular file"), std::string::npos) << got.rejected;
  EXPECT_FALSE(fs::exists(fs::symlink_status(path))) << "removed";
  fs::create_symlink("/dev/zero", path);
  got = load();
  EXPECT_FALSE(got.trace.has_value());
  EXPECT_NE(got.rejected, "");
  EXPECT_FALSE(fs::exists(fs::symlink_status(path))) << "the link removed, not its target";
  fs::create_directories(path / "inside");
  got = load();
  EXPECT_FALSE(got.trace.has_value());
  EXPECT_NE(got.rejected.find("could not be removed"), std::string::npos) << got.rejected;
  fs::remove_all(path);
  // And an entry that verifies is then stored and read as usual.
  ASSERT_TRUE(cache.store("k", r.out.trace));
  EXPECT_TRUE(load().trace.has_value());
}

TEST(TraceCache, RemovesWhatInterruptedStoresLeft) {
  const test::TempDir dir;
  const TraceCache cache(dir.path().string());
  const Rendered r = render_builtin("crowd", 0);
  char buf[256] = {};
  ASSERT_EQ(::gethostname(buf, sizeof buf - 1), 0);
  std::string host = buf;
  for (char& c : host)
    if (c == '.' || c == '/') c = '_';
  // Process 999999999 cannot exist (Linux pids stay below 2^22).
  const fs::path dead = dir.path() / ("x.tmp." + host + ".999999999");
  const fs::path old = dir.path() / "y.tmp.otherhost.12";
  const fs::path live = dir.path() / ("z.tmp.otherhost." + std::to_string(::getpid()));
  const fs::path mine = dir.path() / ("w.tmp." + host + "." + std::to_string(::getpid()));
  for (const auto& p : {dead, old, live, mine}) write_file(p, "half an entry");
  fs::last_write_time(old, fs::file_time_type::clock::now() - std::chrono::hours(2));
  ASSERT_TRUE(cache.store("k", r.out.trace));
  EXPECT_FALSE(fs::exists(dead)) << "its process is gone";
  EXPECT_FALSE(fs::exists(old)) << "older than an hour";
  EXPECT_TRUE(fs::exists(live)) << "another host's store may still be running";
  EXPECT_TRUE(fs::exists(mine)) << "a store of a running process";
}

TEST(TraceCache, SizeLimitIsAWholeNumberOfMegabytes) {
  const char* old = std::getenv("OOVR_CACHE_MAX_MB");
  const std::string saved = old ? old : "";
  for (const char* bad : {" -5", "-5", "0", "12MB", "1e3", "99999999999999"}) {
    ::setenv("OOVR_CACHE_MAX_MB", bad, 1);
    EXPECT_THROW(TraceCache("/tmp/x"), Error) << bad;
  }
  ::setenv("OOVR_CACHE_MAX_MB", "12", 1);
  EXPECT_EQ(TraceCache("/tmp/x").max_bytes(), uint64_t(12) << 20);
  if (old) ::setenv("OOVR_CACHE_MAX_MB", saved.c_str(), 1);
  else ::unsetenv("OOVR_CACHE_MAX_MB");
}

// The experiment, done for every part of an entry: flip a byte of a
// cached trace and run again. Each run must equal an uncached one, say
// once that an entry did not verify, and leave a good entry behind.
// Windows of the crowd scene at 96x64 per eye, cached in the test's own
// folder.
class CrowdWindows : public ::testing::Test {
 protected:
  const test::TempDir dir;
  const CacheDirectory env{dir.path()};
  const std::shared_ptr<const Scene> scene = std::make_shared<const Scene>(BuiltinScenes::find("crowd")->make());
  const StereoRig rig = parse_eye_resolution("96x64");
  const Config config{};
  WindowRequest w;
};

// A window loaded on its own thread hands out, frame by frame, the traces
// load_window makes, held in memory or streamed; the whole window after.
TEST_F(CrowdWindows, ALoaderHandsOutTheTracesLoadWindowMakes) {
  w.first = 5;
  w.count = 4;
  w.use_cache = false;
  const FrameWindow fresh = load_window(scene, rig, config, w);
  ASSERT_EQ(fresh.traces.size(), 4u);
  for (const uint64_t budget : {uint64_t(0), uint64_t(1)}) {  // 1 byte: streamed
    w.memory_budget = budget;
    WindowLoader loader(scene, rig, MachineSpec::from_config(config), w);
    ASSERT_EQ(loader.frames().size(), 4u);
    for (size_t k = 0; k < 4; ++k)
      EXPECT_EQ(serialize_trace(*loader.frames().at(k)), serialize_trace(*fresh.traces[k]))
          << "frame " << k << " budget " << budget;
    EXPECT_THROW(loader.frames().at(4), Error);
    const std::shared_ptr<const FrameWindow> whole = loader.wait();
    ASSERT_TRUE(whole);
    EXPECT_EQ(whole->streamed, budget == 1);
    EXPECT_EQ(whole->frames->size(), 4u);
    EXPECT_EQ(serialize_trace(*whole->frames->at(3)), serialize_trace(*fresh.traces[3]));
    EXPECT_GE(loader.seconds(), 0.0);
  }
}

// A window draws a picture only for its first frame, and only when asked
// (the GPM and traffic images): every other frame is drawn as its trace
// alone, the trace the picture's pass makes.
TEST_F(CrowdWindows, OnlyAFirstFrameAskedForIsDrawnWithItsPicture) {
  w.first = 2;
  w.count = 3;
  w.use_cache = false;
  const FrameWindow plain = load_window(scene, rig, config, w);
  w.need_first_image = true;
  const FrameWindow pictured = load_window(scene, rig, config, w);
  ASSERT_EQ(plain.outputs.size(), 3u);
  ASSERT_EQ(pictured.outputs.size(), 3u);
  const FrameOutput& first = pictured.outputs.front();
  EXPECT_EQ(first.colour.width, rig.frame_width());
  EXPECT_EQ(first.colour.rgba.size(), size_t(rig.frame_width()) * size_t(rig.frame_height()) * 4);
  EXPECT_EQ(first.object_id.size(), size_t(rig.frame_width()) * size_t(rig.frame_height()));
  for (size_t k = 0; k < 3; ++k) {
    if (k > 0) {
      EXPECT_TRUE(pictured.outputs[k].colour.rgba.empty()) << "frame " << k;
    }
    EXPECT_TRUE(plain.outputs[k].colour.rgba.empty()) << "frame " << k;
    EXPECT_TRUE(plain.outputs[k].object_id.empty()) << "frame " << k;
    EXPECT_EQ(serialize_trace(plain.outputs[k].trace), serialize_trace(pictured.outputs[k].trace)) << "frame " << k;
  }
}

// The loader's error reaches whoever waits for a frame, and wait().
TEST_F(CrowdWindows, ALoadersErrorReachesTheSchemesAndTheCaller) {
  w.first = 100000;
  w.count = 2;
  WindowLoader loader(scene, rig, MachineSpec::from_config(config), w);
  try {
    loader.frames().at(1);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loader.wait(), Error);
}

TEST_F(CrowdWindows, ACorruptEntryIsAMissWithTheUncachedResults) {
  w.first = 3;
  w.count = 1;
  w.use_cache = false;
  const FrameWindow fresh = load_window(scene, rig, config, w);
  const SchemeResult expected = run_scheme_window("oo-vr", *fresh.scene, fresh.traces, config, 1);
  w.use_cache = true;
  ASSERT_EQ(load_window(scene, rig, config, w).cached, 0);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir.path())) files.push_back(e.path());
  ASSERT_EQ(files.size(), 1u);
  const fs::path entry = files.front();
  const std::string good = read_file(entry);
  const FrameTrace& t = fresh.outputs.front().trace;
  // The entry's parts: magic, format, key length, key, payload size,
  // checksum; then the payload's header, and each section's count and data.
  const size_t header = 8 + 4 + 4 + 16 + 8 + 8;
  const size_t objects = header + 4 * 9 + 1, tiles = objects + 8 + t.objects.size() * sizeof(ObjectWork);
  const size_t lines = tiles + 8 + t.tiles.size() * sizeof(TileWork);
  ASSERT_EQ(lines + 8 + t.tex_lines.size() * sizeof(TexLine), good.size());
  const std::vector<std::pair<const char*, size_t>> places = {
      {"magic", 0},
      {"format", 8},
      {"key length", 12},
      {"key", 20},
      {"payload size", 32},
      {"checksum", 43},
      {"frame", header},
      {"frame width", header + 4},
      {"tile size", header + 12},
      {"block width", header + 28},
      {"texture format", header + 36},
      {"object count", objects},
      {"an object", objects + 8 + sizeof(ObjectWork) / 2},
      {"tile count", tiles + 1},
      {"a tile's object", tiles + 8},
      {"a tile's counts", tiles + 8 + 20},
      {"the middle tile", tiles + 8 + t.tiles.size() / 2 * sizeof(TileWork) + 6},
      {"line count", lines},
      {"a texture line", lines + 8 + t.tex_lines.size() / 3 * sizeof(TexLine) + 5},
      {"the last byte", good.size() - 1},
  };
  for (const auto& [what, at] : places) {
    for (const uint8_t flip : {uint8_t(0x01), uint8_t(0x80), uint8_t(0xff)}) {
      std::string bad = good;
      bad[at] = char(uint8_t(bad[at]) ^ flip);
      write_file(entry, bad);
      const FrameWindow got = load_window(scene, rig, config, w);
      EXPECT_EQ(got.cached, 0) << what;
      ASSERT_EQ(got.notes.size(), 1u) << what;
      EXPECT_NE(got.notes.front().find("did not verify and was rendered again"), std::string::npos) << got.notes.front();
      EXPECT_EQ(got.outputs.front().trace.tiles, t.tiles) << what;
      EXPECT_EQ(got.outputs.front().trace.tex_lines, t.tex_lines) << what;
      const SchemeResult r = run_scheme_window("oo-vr", *got.scene, got.traces, config, 1);
      EXPECT_EQ(r.frame_latency_s, expected.frame_latency_s) << what;
      EXPECT_EQ(r.total_inter_gpm_bytes(), expected.total_inter_gpm_bytes()) << what;
      // Replaced: the next run is a hit that says nothing.
      const FrameWindow again = load_window(scene, rig, config, w);
      EXPECT_EQ(again.cached, 1) << what;
      EXPECT_TRUE(again.notes.empty()) << what;
      EXPECT_EQ(read_file(entry), good) << what;
    }
  }
  // A whole, well-formed entry of another scene written under this key.
  const Scene other = BuiltinScenes::find("courtyard")->make();
  const StereoView view = make_stereo_view(other.camera, 3, rig);
  const std::string key = entry.stem().string();
  write_file(entry, encode_entry(key, render_frame(other, view, PipelineSettings{}, 3).trace));
  const FrameWindow got = load_window(scene, rig, config, w);
  EXPECT_EQ(got.cached, 0);
  ASSERT_EQ(got.notes.size(), 1u);
  EXPECT_EQ(run_scheme_window("oo-vr", *got.scene, got.traces, config, 1).frame_latency_s, expected.frame_latency_s);
}

// A window beyond the memory budget is streamed from disk: the same numbers
// as in memory, frame by frame, for schemes with one frame at a time and
// with frames in flight, and its folder is gone afterwards.
TEST_F(CrowdWindows, AStreamedWindowGivesTheNumbersOfOneInMemory) {
  w.first = 5;
  w.count = 8;
  const FrameWindow memory = load_window(scene, rig, config, w);
  EXPECT_FALSE(memory.streamed);
  w.memory_budget = 1;
  fs::path folder;
  {
    const FrameWindow streamed = load_window(scene, rig, config, w);
    ASSERT_TRUE(streamed.streamed);
    EXPECT_TRUE(streamed.traces.empty());
    ASSERT_EQ(streamed.frames->size(), 8u);
    ASSERT_FALSE(streamed.notes.empty());
    EXPECT_NE(streamed.notes.back().find("streamed through"), std::string::npos) << streamed.notes.back();
    for (const auto& e : fs::directory_iterator(dir.path()))
      if (e.is_directory()) folder = e.path();
    ASSERT_FALSE(folder.empty());
    for (size_t k = 0; k < 8; ++k) EXPECT_EQ(streamed.frames->at(k)->tiles, memory.traces[k]->tiles) << k;
    for (const char* scheme : {"baseline", "afr", "oo-vr"}) {
      const SchemeResult a = run_scheme_window(scheme, *memory.scene, *memory.frames, config, 8);
      const SchemeResult b = run_scheme_window(scheme, *streamed.scene, *streamed.frames, config, 8);
      EXPECT_EQ(a.frame_latencies_s, b.frame_latencies_s) << scheme;
      EXPECT_EQ(a.total_inter_gpm_bytes(), b.total_inter_gpm_bytes()) << scheme;
    }
  }
  EXPECT_FALSE(fs::exists(folder)) << "the streamed window's folder is removed with it";
}

// A session (the Python module's) renders a window once and replays it for
// every configuration whose traces are the same; another line size, a
// first image or an uncached request load again; the budget drops the
// least recently used window.
TEST_F(CrowdWindows, ASessionRendersEachWindowOnceAndKeepsItWithinItsBudget) {
  TraceSession session(uint64_t(1) << 30);
  w.count = 2;
  w.use_cache = false;  // the test's cache folder is empty anyway: count renders, not disk hits
  const auto first = session.window("crowd", rig, config, w);
  EXPECT_EQ(session.stats().frames_rendered, 2u);
  EXPECT_EQ(session.stats().scenes_loaded, 1u);
  w.use_cache = true;
  Config links = config;
  links.set("link.bandwidth=32GBps");  // not a pipeline setting: the same traces
  EXPECT_EQ(session.window("crowd", rig, links, w), first);
  w.count = 1;
  EXPECT_EQ(session.window("crowd", rig, config, w), first) << "a longer window covers a shorter one";
  EXPECT_EQ(session.stats().windows_reused, 2u);
  EXPECT_EQ(session.stats().frames_rendered, 2u);

  Config lines = config;
  lines.set("memory.line=64B");  // the trace's line addresses change
  const auto other = session.window("crowd", rig, lines, w);
  EXPECT_NE(other, first);
  EXPECT_EQ(other->outputs.front().trace.line_bytes, 64u);
  EXPECT_EQ(session.stats().windows_held, 2u);
  EXPECT_EQ(session.stats().scenes_loaded, 1u) << "the scene is loaded once";

  w.count = 2;
  w.need_first_image = true;  // held without it: cached traces carry no picture
  const auto again = session.window("crowd", rig, config, w);
  EXPECT_FALSE(again->outputs.front().colour.rgba.empty());

  TraceSession small(1);  // one byte: only the window in use stays
  (void)small.window("crowd", rig, config, w);
  (void)small.window("crowd", rig, lines, w);
  EXPECT_EQ(small.stats().windows_held, 1u);
  w.first = 1000;
  EXPECT_THROW(session.window("crowd", rig, config, w), Error);
  EXPECT_THROW(session.window("no-such-scene", rig, config, w), Error);
}

}  // namespace
}  // namespace oovr
