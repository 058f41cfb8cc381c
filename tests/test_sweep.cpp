// Sweep files, point ids, the sweep engine and the results database
// (docs/sweeps.md, docs/results.md).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <future>
#include <map>
#include <set>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/results_writer.h"
#include "oovr/experiments/slurm.h"
#include "oovr/experiments/sweep.h"
#include "oovr/experiments/sweep_run.h"
#include "oovr/run/result_json.h"
#include "oovr/run/result_metrics.h"
#include "temp_dir.h"
#include "test_util.h"

namespace oovr {
namespace {

using test::message_of;

Sweep parse(const std::string& text) { return parse_sweep(text, "t.toml", ""); }

// A scheme's own section, as a scheme added with a key of its own brings
// one (no registered scheme names it): only in this test program, not in
// the oovr that wrote the ids below.
const ConfigSections::Add kAddedSchemeKeys("test_added", {"a scheme added with a key of its own",
                                                          [](const Config& c) { (void)c.get_int("test_added.knob", 7, 0, 9); },
                                                          {{"test_added.knob", "a setting of an added scheme"}},
                                                          true});

TEST(Sweep, CrossProductWithSchemesInnermost) {
  Sweep s = parse(R"(
scenes = ["crowd", "courtyard"]
schemes = ["baseline", "oo-vr"]
resolutions = ["160x128", "320x256"]
frames = 4
[set]
"memory.placement" = "first-touch"
[sweep]
"link.bandwidth" = ["32GBps", "64GBps", "1TBps"]
)");
  ASSERT_EQ(s.points.size(), 2u * 2u * 2u * 3u);
  EXPECT_EQ(s.name, "t");
  EXPECT_EQ(s.swept_keys, std::vector<std::string>{"link.bandwidth"});
  EXPECT_EQ(s.points[0].scheme, "baseline");
  EXPECT_EQ(s.points[1].scheme, "oo-vr");
  EXPECT_EQ(s.points[0].swept.at("link.bandwidth"), "32GBps");
  EXPECT_EQ(s.points[2].swept.at("link.bandwidth"), "64GBps");
  EXPECT_EQ(s.points[6].resolution, "320x256");
  EXPECT_EQ(s.points[12].scene, "courtyard");
  // Fixed settings come first, the swept value after.
  ASSERT_EQ(s.points[0].settings.size(), 2u);
  EXPECT_EQ(s.points[0].settings[0].first, "memory.placement");
  resolve_all(s);
  std::set<std::string> ids;
  for (const auto& p : s.points) {
    EXPECT_EQ(p.id.size(), 16u);
    ids.insert(p.id);
    EXPECT_EQ(p.window, 4);
  }
  EXPECT_EQ(ids.size(), s.points.size());
}

TEST(Sweep, PointsInheritWhatTheyLeaveOut) {
  Sweep s = parse(R"(
scenes = ["crowd"]
resolutions = ["160x128"]
[sweep]
gpms = [2, 4]
[[point]]
scheme = "baseline-1tb"
sweep = {}
[[point]]
schemes = ["afr", "object"]
set = { "link.bandwidth" = "128GBps" }
)");
  // No schemes at the top level: no grid there, only the points.
  ASSERT_EQ(s.points.size(), 1u + 2u * 2u);
  EXPECT_EQ(s.points[0].scheme, "baseline-1tb");
  EXPECT_TRUE(s.points[0].swept.empty());
  EXPECT_EQ(s.points[1].scheme, "afr");
  EXPECT_EQ(s.points[1].scene, "crowd");
  EXPECT_EQ(s.points[1].swept.at("gpms"), "2");
  EXPECT_EQ(s.points[1].settings.front(), (std::pair<std::string, std::string>{"link.bandwidth", "128GBps"}));
  resolve_all(s);
  // frames left out: one per GPM (AFR's frames in flight), as oovr compare.
  EXPECT_EQ(s.points[1].window, 2);
  EXPECT_EQ(s.points[3].window, 4);
}

TEST(Sweep, IdsDependOnWhatDeterminesTheResultOnly) {
  const auto id = [](const std::string& text) {
    Sweep s = parse(text);
    resolve_all(s);
    return s.points.front().id;
  };
  const std::string a = id("scenes = ['crowd']\nschemes = ['baseline']\n[set]\n'link.bandwidth' = '64GBps'\n");
  // The same value spelled otherwise, or left at its default: the same point.
  EXPECT_EQ(a, id("scenes = ['crowd']\nschemes = ['baseline']\n[set]\n'link.bandwidth' = '0.064TBps'\n"));
  EXPECT_EQ(a, id("name = 'other'\nscenes = ['crowd']\nschemes = ['baseline']\n"));
  // A different value, scheme, frame count or scene: another point.
  EXPECT_NE(a, id("scenes = ['crowd']\nschemes = ['baseline']\n[set]\n'link.bandwidth' = '32GBps'\n"));
  EXPECT_NE(a, id("scenes = ['crowd']\nschemes = ['object']\n"));
  EXPECT_NE(a, id("scenes = ['crowd']\nschemes = ['baseline']\nframes = 8\n"));
  EXPECT_NE(a, id("scenes = ['courtyard']\nschemes = ['baseline']\n"));
  EXPECT_EQ(stable_id(""), "cbf29ce484222325");  // FNV-1a 64's offset basis
  EXPECT_EQ(stable_id("a"), "af63dc4c8601ec8c");
}

// A point's id hashes the keys its run reads: the machine's and its
// scheme's own. The ids are those `oovr sweep --list` gives for the file
// (an oovr without the section above): adding a scheme with a key of its
// own changes no stored id, so `--resume` re-runs nothing. A key added to
// a scheme's own section changes the ids of that scheme's points only:
// OO-VR's was 5c7dc1f515043f62 before its section gained oo.split_share,
// and d761a8da547c6e41 before it took the sort_last section's
// sort_last.composition; the baseline's is what it was. (Every id changes when the machine gains
// a key, as it must: its runs could differ. The energy keys of issue 30 did:
// 6bd0ffd58f119c57 and 69d86cf59776c8c1 before them.)
TEST(Sweep, AnIdHashesTheMachinesKeysAndItsSchemesOwnOnly) {
  Sweep s = parse("scenes = ['crowd']\nschemes = ['baseline', 'oo-vr']\nresolutions = ['96x64']\nframes = 1\n");
  resolve_all(s);
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_NE(s.points[0].machine.entries.count("test_added.knob"), 0u);  // read, as every key is checked
  for (const SweepPoint& p : s.points) EXPECT_EQ(p.canonical.find("test_added"), std::string::npos) << p.scheme;
  EXPECT_EQ(s.points[0].canonical.find("oo.tsl_threshold"), std::string::npos);  // OO-VR's, not the baseline's
  EXPECT_NE(s.points[1].canonical.find("oo.tsl_threshold"), std::string::npos);
  EXPECT_EQ(s.points[0].id, "5a9be17b3e1ba58b");
  EXPECT_EQ(s.points[1].id, "6e6661a064570585");
  // A point cannot set a key its scheme does not read: points differing in
  // it alone would be one run.
  Sweep bad = parse("scenes = ['crowd']\nschemes = ['baseline']\n[set]\n'oo.batch_queue' = 8\n");
  const std::string why = message_of([&] { resolve_all(bad); });
  EXPECT_NE(
      why.find(
          "'oo.batch_queue' is a setting of the schemes with the 'oo' section (oo-app, oo-vr, oo-vr-affinity), not of baseline"),
      std::string::npos)
      << why;
  // The composition algorithm is a setting of the sort-last schemes.
  Sweep per_eye = parse("scenes = ['crowd']\nschemes = ['per-eye']\n[set]\n'sort_last.composition' = 'binary-swap'\n");
  const std::string no = message_of([&] { resolve_all(per_eye); });
  EXPECT_NE(no.find("'sort_last.composition' is a setting of the schemes with the 'sort_last' section"), std::string::npos) << no;
}

// Points that are one run (the machine's own value in a swept list, a
// scene named twice) run once: the later ones go, said in words, and the
// earlier takes the swept values it lacked.
TEST(Sweep, PointsThatAreTheSameRunAreRunOnceAndShared) {
  Sweep twice = parse("scenes = ['crowd', 'crowd']\nschemes = ['baseline']\nresolutions = ['96x64']\n");
  resolve_all(twice);
  ASSERT_EQ(twice.points.size(), 1u);
  ASSERT_EQ(twice.shared.size(), 1u);
  EXPECT_NE(twice.shared[0].find("point 2 (crowd, baseline, 96x64) is the same run as an earlier point"), std::string::npos)
      << twice.shared[0];
  Sweep s = parse(R"(
scenes = ["crowd"]
schemes = ["baseline", "oo-vr"]
resolutions = ["96x64"]
[[point]]
schemes = ["baseline"]
sweep = { "link.bandwidth" = ["32GBps", "64GBps", "0.064TBps"] }
)");
  resolve_all(s);
  // The grid's two, then 32 GB/s; 64 GB/s (the default) twice is the grid's baseline.
  ASSERT_EQ(s.points.size(), 3u);
  EXPECT_EQ(s.shared.size(), 2u);
  EXPECT_EQ(s.points[0].scheme, "baseline");
  EXPECT_EQ(s.points[0].swept.at("link.bandwidth"), "64GBps");
  EXPECT_EQ(s.points[1].swept.count("link.bandwidth"), 0u);
  EXPECT_EQ(s.points[2].swept.at("link.bandwidth"), "32GBps");
  std::set<std::string> ids;
  for (const SweepPoint& p : s.points) ids.insert(p.id);
  EXPECT_EQ(ids.size(), 3u);
}

// A sweep on a machine (`oovr paper --config/--set`): the preset's keys,
// the file's [set] and --set's, in that order, are the machine, written
// whole into the text's [set]; the points keep their own settings on top,
// and a scheme's key on the machine is only its schemes'.
TEST(Sweep, OnAMachineEveryPointStartsFromItAndKeepsItsOwnSettings) {
  test::TempDir dir;
  const std::string preset = dir.file("hbm.toml", "[link]\nbandwidth = \"256GBps\"\n[memory]\nline = 128\n");
  const std::string text = R"(
scenes = ["crowd"]
schemes = ["baseline", "oo-vr"]
resolutions = ["96x64"]
[set]
"dram.latency" = "120ns"
[[point]]
schemes = ["baseline"]
sweep = { "link.bandwidth" = ["32GBps", "256GBps"] }
)";
  std::map<std::string, std::string> sources;
  const std::string on = sweep_on_machine(text, "t.toml", "", preset, {"oo.batch_queue=8", "dram.latency=150ns"}, 0, &sources);
  EXPECT_EQ(on.find("config ="), std::string::npos);
  EXPECT_EQ(sources.at("link.bandwidth"), preset + ":2");
  EXPECT_EQ(sources.at("oo.batch_queue"), "--set");
  EXPECT_EQ(sources.at("dram.latency"), "--set");  // --set after the file's [set]
  Sweep s = parse_sweep(on, "t.toml", "");
  const Config machine = resolve_on_machine(s, sources);
  // 256 GB/s swept is the machine's: the grid's baseline, run once.
  ASSERT_EQ(s.points.size(), 3u);
  EXPECT_EQ(s.shared.size(), 1u);
  EXPECT_TRUE(s.points[0].settings.empty());
  EXPECT_EQ(s.points[0].machine.entries.at("link.bandwidth").value, "256 GB/s");
  EXPECT_EQ(s.points[0].machine.entries.at("link.bandwidth").source, preset + ":2");
  EXPECT_EQ(s.points[0].machine.entries.at("dram.latency").value, "150ns");
  EXPECT_EQ(s.points[1].machine.entries.at("oo.batch_queue").value, "8");
  EXPECT_EQ(s.points[2].machine.entries.at("link.bandwidth").value, "32 GB/s");  // its own
  // The baseline does not read oo.batch_queue: its id is that of the same
  // machine without it; OO-VR's is not.
  Sweep without = parse_sweep(sweep_on_machine(text, "t.toml", "", preset, {"dram.latency=150ns"}), "t.toml", "");
  resolve_on_machine(without);
  EXPECT_EQ(without.points[0].id, s.points[0].id);
  EXPECT_NE(without.points[1].id, s.points[1].id);
  // The same machine as a sweep would have it: the same ids.
  Sweep as_sweep = parse(std::string(R"(
scenes = ["crowd"]
schemes = ["baseline"]
resolutions = ["96x64"]
[set]
"link.bandwidth" = "256GBps"
"dram.latency" = "150ns"
)"));
  resolve_all(as_sweep);
  EXPECT_EQ(as_sweep.points[0].id, s.points[0].id);
  EXPECT_EQ(machine.entries().count("link.bandwidth"), 0u);  // the machine's entries are what its readers record
  // Nothing to write: the text itself.
  EXPECT_EQ(sweep_on_machine("scenes = ['crowd']\nschemes = ['baseline']\n", "t.toml", "", "", {}),
            "scenes = ['crowd']\nschemes = ['baseline']\n");
  // A file's name cannot end the text's first line, a comment, and be read
  // as TOML; a value with a new line is no value of any key.
  const std::string odd = sweep_on_machine(text, "t\n[evil]\n.toml", "", "", {"gpms=2"});
  EXPECT_EQ(odd.find("\n[evil]"), std::string::npos) << odd;
  EXPECT_NO_THROW(parse_sweep(odd, "t.toml", ""));
  EXPECT_NE(message_of([&] {
              sweep_on_machine(text, "t.toml", "", "", {"memory.placement=first-touch\n[evil]"});
            }).find("memory.placement"),
            std::string::npos);
  // Bad input is named.
  EXPECT_NE(message_of([&] {
              sweep_on_machine(text, "t.toml", "", "", {"link.bandwith=1TBps"});
            }).find("unknown configuration key 'link.bandwith' (--set)"),
            std::string::npos);
  EXPECT_NE(message_of([&] { sweep_on_machine(text, "t.toml", "", "", {"gpms"}); }).find("--set gpms: give key=value"),
            std::string::npos);
  EXPECT_NE(message_of([&] { sweep_on_machine(text, "t.toml", "", (dir.path() / "none.toml").string(), {}); }).find("none.toml"),
            std::string::npos);
  EXPECT_NE(message_of([&] {
              sweep_on_machine("scenes = ['crowd']\nschemes = ['baseline']\n[[point]]\nframes = 2\n", "t.toml", "", "", {}, 8);
            }).find("--frames: a point of the sweep 't.toml' sets its own frames"),
            std::string::npos);
  Sweep eight = parse_sweep(sweep_on_machine("scenes = ['crowd']\nschemes = ['afr']\nresolutions = ['96x64']\nframes = 4\n",
                                             "t.toml", "", "", {"gpms=8"}, 8),
                            "t.toml", "");
  resolve_on_machine(eight);
  EXPECT_EQ(eight.points[0].window, 8);
}

TEST(Sweep, BadFilesAreRefusedNamingWhatIsWrong) {
  const auto error = [](const std::string& text) {
    return message_of([&] {
      Sweep s = parse(text);
      resolve_all(s);
    });
  };
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['baseline']\ncolour = 1\n").find("unknown key 'colour'"), std::string::npos);
  EXPECT_NE(error("scenes = []\nschemes = ['baseline']\n").find("scenes is an empty list"), std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\n").find("no points"), std::string::npos);
  EXPECT_NE(error("schemes = ['baseline']\n").find("names no scene"), std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['baseline']\nframes = 0\n").find("frames = 0 is outside 1 to 1000"),
            std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['baseline']\nresolutions = ['big']\n").find("line 3"), std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['baseline']\n[sweep]\ngpms = 4\n").find("takes a list"), std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['baseline']\n[set]\ngpms = [4]\n").find("swept values go in [sweep]"),
            std::string::npos);
  // Resolved against the machine: a bad value or key names the point.
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['baseline']\n[sweep]\ngpms = [4, 99]\n").find("point (crowd, baseline"),
            std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['baseline']\n[set]\n'link.bandwith' = '1TBps'\n").find("link.bandwith"),
            std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['nope']\n").find("unknown scheme 'nope'"), std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['afr']\nframes = 3\n").find("must be a multiple of 4"), std::string::npos);
  // A list that would expand past the limit is refused before it is.
  std::string big = "scenes = ['crowd']\nschemes = ['baseline']\n[sweep]\n";
  for (const char* k : {"a", "b", "c", "d", "e"}) {
    big += std::string("'") + k + "' = [";
    for (int i = 0; i < 20; ++i) big += std::to_string(i) + ",";
    big += "]\n";
  }
  EXPECT_NE(error(big).find("more than 100000 points"), std::string::npos);
}

// One value, one spelling: a file giving a value twice had one of them
// dropped silently. Names and values are bounded and printable, and the
// point cap counts what the points hold (a 900,000-character scene name made
// 2,025 points take 3.6 GB).
TEST(Sweep, TwoSpellingsOfOneValueAndOversizedNamesAreRefused) {
  const auto error = [](const std::string& text) { return message_of([&] { (void)parse_sweep(text, "t.toml", ""); }); };
  EXPECT_NE(error("scene = 'crowd'\nscenes = ['courtyard']\nschemes = ['baseline']\n").find("scenes and scene both given"),
            std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nscheme = 'afr'\nschemes = ['baseline']\n").find("schemes and scheme both given"),
            std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['afr']\nresolution = '64x64'\nresolutions = ['64x64']\n")
                .find("resolutions and resolution both given"),
            std::string::npos);
  EXPECT_NE(
      error("scenes = ['crowd']\nschemes = ['afr']\n[sweep]\n'link.bandwidth' = ['1TBps']\n[sweep.link]\nbandwidth = ['2TBps']\n")
          .find("sweep.link.bandwidth is given twice"),
      std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['afr']\n[set]\n'link.bandwidth' = '1TBps'\n[set.link]\nbandwidth = '2TBps'\n")
                .find("set.link.bandwidth is given twice"),
            std::string::npos);
  EXPECT_NE(error("scenes = ['crowd']\nschemes = ['afr']\n[set]\ngpms = 2\n[sweep]\ngpms = [4, 8]\n")
                .find("gpms is both set and swept"),
            std::string::npos);
  EXPECT_NE(error("scenes = ['" + std::string(900000, 'x') + "']\nschemes = ['baseline']\n").find("more than 4096 characters"),
            std::string::npos);
  EXPECT_NE(error("scenes = [\"a\\u001b[31m\"]\nschemes = ['baseline']\n").find("control characters"), std::string::npos);
  // 100,000 points are within the cap; with 4,000-character scene names
  // they would hold about 3.3 GB, and are refused before they are made.
  const auto grid = [](size_t name_chars) {
    std::string t = "schemes = ['baseline']\nscenes = [";
    for (int i = 0; i < 100; ++i) {
      t += '\'';
      t.append(name_chars, 'x');
      t += std::to_string(i);
      t += "',";
    }
    t += "]\n[sweep]\na = [";
    for (int i = 0; i < 1000; ++i) t += std::to_string(i) + ",";
    return t + "]\n";
  };
  EXPECT_EQ(error(grid(1)), "<no error>");
  EXPECT_NE(error(grid(4000)).find("would hold about"), std::string::npos);
  // The name reaches a shell script, file names, HTML and the terminal.
  EXPECT_NE(error("name = \"x\\ntouch PWNED\\n#\"\nscenes = ['crowd']\nschemes = ['baseline']\n").find("is not a sweep name"),
            std::string::npos);
  EXPECT_NE(error("name = '../x'\nscenes = ['crowd']\nschemes = ['baseline']\n").find("is not a sweep name"), std::string::npos);
  EXPECT_NE(message_of([] {
              (void)parse_sweep("scenes = ['crowd']\nschemes = ['baseline']\n", "my sweep.toml", "");
            }).find("its file's name 'my sweep' is not one"),
            std::string::npos);
  EXPECT_TRUE(is_sweep_name("paper-2.v1_x"));
  EXPECT_FALSE(is_sweep_name("-x"));
  EXPECT_FALSE(is_sweep_name(std::string(65, 'a')));
}

// A record as oovr makes them (check_run_record holds): its result a
// two-GPM frame of `ms` milliseconds, its metrics those the result gives,
// its id the hash of its setup (scene "crowd" + `tag`).
RunRecord sample_record(const std::string& tag, double ms) {
  RunRecord r;
  r.sweep = "t";
  r.scene = "crowd" + tag;
  r.scheme = "baseline";
  r.resolution = "160x128";
  r.frames = 4;
  r.swept["link.bandwidth"] = 32e9;
  r.config = {{"gpms", {{"value", "2"}, {"base", 2.0}, {"source", "default"}}},
              {"link.bandwidth", {{"value", "32 GB/s"}, {"base", 32e9}, {"unit", "B/s"}, {"source", "sweep"}}}};
  r.status = "done";
  r.oovr_version = "0.1";
  r.git_commit = "abc";
  r.command = "oovr sweep t.toml";
  r.host = "h";
  r.started = "2026-11-24T00:00:00Z";
  SchemeResult sr;
  sr.scheme = "baseline";
  sr.gpms = 2;
  sr.frequency_hz = 1e9;
  sr.frame_latency_s = ms * 1e-3;
  sr.frame_latencies_s = {ms * 1e-3};
  sr.throughput_fps = 1e3 / ms;
  sr.gpm_busy_s = {ms * 1e-3, ms * 0.5e-3};
  for (const char* level : {"l1", "l2", "remote_cache", "home_l2", "dram"}) sr.stats.count(level, "served", 0);
  sr.stats.count("memory", "accesses", 0);
  sr.stats.count("gpm[0].dram", "bytes", 4096, "B");
  sr.stats.count("gpm[1].dram", "bytes", 2048, "B");
  sr.stats.count("link[0->1]", "bytes", 1024, "B");
  sr.stats.count("gpm[0]->gpm[1]", "bytes", 1024, "B");
  sr.stats.count("gpm[1]->gpm[0]", "bytes", 0, "B");
  r.result = to_json(sr);
  r.metrics = metrics_of(sr);
  r.images = {{"gpm", 2, 1, std::string("\x89PNG\0\x01", 6), "{\"gpm0\":\"#e6194b\"}"}};
  r.id = stable_id(canonical_setup(r));
  return r;
}

// A sweep given as data (the Python module's dicts) reads as the file with
// the same keys: the same points, ids and columns; what TOML cannot hold is
// refused naming it; an unknown key keeps its kind (KeyError in Python).
TEST(Sweep, ADefinitionGivenAsDataIsTheFileWithItsKeys) {
  const auto j = nlohmann::json::parse(R"({"name": "d", "scenes": ["crowd"], "schemes": ["baseline", "afr"],
    "resolutions": ["160x128"], "frames": 4, "images": true, "set": {"gpm.draw_cycles": 0.5},
    "sweep": {"link.bandwidth": ["32GBps", "1TBps"], "gpms": [2, 4]},
    "point": [{"scheme": "object", "sweep": {}}]})");
  Sweep a = parse_sweep(sweep_toml(j), "d", "");
  Sweep b = parse(R"(
name = "d"
scenes = ["crowd"]
schemes = ["baseline", "afr"]
resolutions = ["160x128"]
frames = 4
images = true
[set]
"gpm.draw_cycles" = 0.5
[sweep]
"link.bandwidth" = ["32GBps", "1TBps"]
gpms = [2, 4]
[[point]]
scheme = "object"
sweep = {}
)");
  resolve_all(a);
  resolve_all(b);
  ASSERT_EQ(a.points.size(), 9u);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i].id, b.points[i].id) << i;
  EXPECT_EQ(a.swept_keys, b.swept_keys);
  EXPECT_TRUE(a.images);
  EXPECT_NE(message_of([&] { (void)sweep_toml(nlohmann::json::parse(R"({"frames": null})")); }).find("sweep.frames is null"),
            std::string::npos);
  EXPECT_THROW(sweep_toml(nlohmann::json::parse("[1, 2]")), Error);
  Sweep unknown = parse_sweep(sweep_toml(nlohmann::json::parse(R"({"scenes": ["crowd"], "schemes": ["baseline"],
    "set": {"no.such.key": 1}})")),
                              "u", "");
  EXPECT_THROW(resolve_all(unknown), UnknownKeyError);
}

TEST(ResultsDb, RunsRoundTripAndAreStoredOnce) {
  test::TempDir dir;
  const std::string path = dir.file("r.db");
  const RunRecord a = sample_record("a", 1.5), b = sample_record("b", 2.5);
  {
    ResultsDb db(path);
    db.add_sweep({"t", "t.toml", "scenes = ['crowd']", "oovr sweep t.toml", {"link.bandwidth"}, 2});
    EXPECT_TRUE(db.insert(b));
    EXPECT_TRUE(db.insert(a));
    RunRecord again = sample_record("a", 9.0);
    EXPECT_EQ(again.id, a.id);
    EXPECT_FALSE(db.insert(again));  // already there: kept as it was
  }
  ResultsDb db(path);  // reopened
  db.verify();
  const auto runs = db.runs();
  ASSERT_EQ(runs.size(), 2u);
  const RunRecord& first = runs[0].id == a.id ? runs[0] : runs[1];
  EXPECT_EQ(first.id, a.id);
  EXPECT_EQ(first.result["frame_latency_s"], 1.5e-3);
  EXPECT_EQ(first.swept.at("link.bandwidth"), 32e9);
  ASSERT_EQ(first.metrics.size(), a.metrics.size());
  EXPECT_GT(first.metrics.size(), 5u);
  ASSERT_EQ(first.images.size(), 1u);
  EXPECT_EQ(first.images[0].data, std::string("\x89PNG\0\x01", 6));  // bytes, not text
  EXPECT_EQ(db.run_status(), (std::map<std::string, std::string>{{a.id, "done"}, {b.id, "done"}}));
  db.remove(a.id);
  EXPECT_EQ(db.runs().size(), 1u);
}

// A database at `path` whose writes fail half-way, after a run's row and
// metrics: its images table refuses every row ('refused').
void make_database_refusing_images(const std::string& path) {
  { ResultsDb created(path); }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(raw, "CREATE TRIGGER no_images BEFORE INSERT ON images BEGIN SELECT RAISE(ABORT, 'refused'); END",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(raw);
}

TEST(ResultsDb, AFailedWriteLeavesNoPartOfTheRun) {
  test::TempDir dir;
  const std::string path = dir.file("r.db");
  make_database_refusing_images(path);
  ResultsDb db(path);
  EXPECT_NE(message_of([&] { db.insert(sample_record("a", 1)); }).find("refused"), std::string::npos);
  EXPECT_TRUE(db.runs().empty());
  RunRecord plain = sample_record("a", 1);
  plain.images.clear();
  EXPECT_TRUE(db.insert(plain));  // and the database is usable after
  EXPECT_EQ(db.runs().size(), 1u);
}

// Whether the database at `path` has the metrics_by_name index.
bool has_metrics_index(const std::string& path) {
  sqlite3* raw = nullptr;
  EXPECT_EQ(sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(raw, "SELECT 1 FROM sqlite_master WHERE type = 'index' AND name = 'metrics_by_name'", -1, &st, nullptr);
  const bool has = sqlite3_step(st) == SQLITE_ROW;
  sqlite3_finalize(st);
  sqlite3_close(raw);
  return has;
}

TEST(ResultsDb, ManyRunsAreWrittenWithTheMetricsIndexBuiltOnceAfter) {
  test::TempDir dir;
  const std::string path = dir.file("r.db");
  ResultsDb db(path);
  db.add_sweep({"t", "t.toml", "scenes = ['crowd']", "oovr sweep t.toml", {"link.bandwidth"}, 2});
  {
    const ResultsDb::Bulk bulk = db.bulk(20);
    EXPECT_FALSE(has_metrics_index(path)) << "dropped while many runs are written";
    for (int i = 0; i < 20; ++i) EXPECT_TRUE(db.insert(sample_record("m" + std::to_string(i), 1.0 + i)));
  }
  EXPECT_TRUE(has_metrics_index(path)) << "built again after";
  {
    const ResultsDb::Bulk bulk = db.bulk(1);  // one run beside 20: kept
    EXPECT_TRUE(has_metrics_index(path));
    EXPECT_TRUE(db.insert(sample_record("one", 1)));
  }
  EXPECT_TRUE(has_metrics_index(path));
  EXPECT_EQ(db.runs().size(), 21u);
  db.verify();
}

// Records handed over while the writer is busy wait, and are written
// together, in the order they came; every one is stored, then announced.
TEST(ResultsWriter, RecordsHandedOverWhileItWritesShareOneTransaction) {
  test::TempDir dir;
  const std::string path = dir.file("r.db");
  ResultsDb db(path);
  db.add_sweep({"t", "t.toml", "scenes = ['crowd']", "oovr sweep t.toml", {"link.bandwidth"}, 2});
  std::promise<void> entered, release;
  std::shared_future<void> go = release.get_future().share();
  std::vector<std::string> announced;
  ResultsWriter writer(db, [&](const RunRecord& r) {
    if (announced.empty()) {
      entered.set_value();
      go.wait();  // the writer is busy with the first record's callback
    }
    announced.push_back(r.id);
  });
  std::vector<std::string> ids;
  RunRecord first = sample_record("w0", 1);
  ids.push_back(first.id);
  writer.record(first);
  entered.get_future().wait();
  for (int i = 1; i <= 20; ++i) {
    RunRecord r = sample_record("w" + std::to_string(i), 1.0 + i);
    ids.push_back(r.id);
    writer.record(std::move(r));
  }
  release.set_value();
  writer.finish();
  EXPECT_EQ(announced, ids);
  EXPECT_EQ(writer.commits(), 2u) << "the twenty waiting records in one transaction";
  EXPECT_EQ(db.runs().size(), 21u);
}

// A mark that a point has started is on disk when mark() returns (a
// reader sees it), and so is the record handed over before it (the point a
// worker ran before: a child running one point at a time that dies has
// only the point it was running marked); the point's record clears it.
TEST(ResultsWriter, AStartingMarkIsOnDiskBeforeThePointRuns) {
  test::TempDir dir;
  const std::string path = dir.file("r.db");
  ResultsDb db(path);
  db.add_sweep({"t", "t.toml", "scenes = ['crowd']", "oovr sweep t.toml", {"link.bandwidth"}, 2});
  const RunRecord before = sample_record("before", 2);
  const RunRecord r = sample_record("m", 1);
  std::vector<std::pair<size_t, bool>> marked;
  ResultsWriter writer(db, {}, [&](const std::vector<size_t>& points, bool starting) {
    marked.push_back({points.at(0), starting});
  });
  writer.mark({before.id}, 4242, {6}, true, false);
  writer.record(before);
  writer.mark({r.id}, 4242, {7}, true, true);
  {
    const ResultsDb reader(path, ResultsDb::Access::read_only);
    const auto flight = reader.in_flight();
    ASSERT_EQ(flight.size(), 1u);
    EXPECT_EQ(flight[0].id, r.id);
    EXPECT_EQ(flight[0].pid, 4242);
    EXPECT_EQ(reader.run_status(), (std::map<std::string, std::string>{{before.id, "done"}}));
  }
  writer.record(r);
  writer.finish();
  EXPECT_TRUE(db.in_flight().empty());
  // Handed over after it finished: an error, not a wait for ever.
  EXPECT_NE(message_of([&] { writer.mark({r.id}, 1, {7}, true, true); }).find("after its writer finished"), std::string::npos);
  EXPECT_THROW(writer.record(sample_record("late", 1)), Error);
  EXPECT_EQ(marked, (std::vector<std::pair<size_t, bool>>{{6, true}, {7, true}}));
}

// The first error, the database's or a callback's, stops the writer and is
// thrown by finish() and by any later hand-over; a failed transaction leaves
// none of its records.
TEST(ResultsWriter, TheFirstErrorStopsItAndIsThrown) {
  test::TempDir dir;
  {
    const std::string path = dir.file("a.db");
    ResultsDb db(path);
    db.add_sweep({"t", "t.toml", "scenes = ['crowd']", "oovr sweep t.toml", {"link.bandwidth"}, 2});
    int calls = 0;
    ResultsWriter writer(db, [&](const RunRecord&) {
      if (++calls == 2) throw Error("the progress display is gone");
    });
    writer.record(sample_record("a", 1));
    writer.record(sample_record("b", 2));
    EXPECT_NE(message_of([&] { writer.finish(); }).find("progress display is gone"), std::string::npos);
    EXPECT_THROW(writer.record(sample_record("c", 3)), Error);
    EXPECT_THROW(writer.mark({"x"}, 1, {0}, true, true), Error);
    EXPECT_EQ(db.runs().size(), 2u) << "stored before they were announced";
  }
  {
    const std::string path = dir.file("b.db");
    make_database_refusing_images(path);
    ResultsDb db(path);
    ResultsWriter writer(db);
    writer.record(sample_record("a", 1));
    EXPECT_NE(message_of([&] { writer.finish(); }).find("refused"), std::string::npos);
    EXPECT_TRUE(db.runs().empty());
  }
}

TEST(ResultsDb, RecordsRoundTripThroughJson) {
  const RunRecord r = sample_record("a", 1.25);
  const RunRecord back = run_record_from_json(nlohmann::ordered_json::parse(to_json(r).dump()));
  EXPECT_EQ(to_json(back).dump(), to_json(r).dump());
  EXPECT_NE(message_of([] {
              (void)run_record_from_json(nlohmann::ordered_json{{"id", "x"}});
            }).find("not an oovr run"),
            std::string::npos);
  EXPECT_NE(message_of([] {
              (void)run_record_from_json(nlohmann::ordered_json{{"schema", "oovr.run"}, {"schema_version", 1}, {"id", "x"}});
            }).find("not oovr's"),
            std::string::npos);
  nlohmann::ordered_json newer = to_json(r);
  newer["schema_version"] = kResultsDbVersion + 1;
  EXPECT_NE(message_of([&] { (void)run_record_from_json(newer); }).find("newer than this oovr's"), std::string::npos);
  for (const std::string& s :
       std::vector<std::string>{"", "f", "fo", "foo", "foob", "fooba", "foobar", std::string("\0\xff\x10", 3)})
    EXPECT_EQ(base64_decode(base64_encode(s)), s);
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64_encode("fo"), "Zm8=");
  EXPECT_FALSE(base64_decode("Zm9=v"));
  EXPECT_FALSE(base64_decode("Z=8A"));
}

TEST(ResultsDb, OtherFilesAreRefused) {
  test::TempDir dir;
  const std::string text = dir.file("notes.txt", "not a database, only some text that is long enough to have a header\n");
  EXPECT_NE(message_of([&] { ResultsDb db(text); }).find("notes.txt"), std::string::npos);
  EXPECT_NE(message_of([&] { ResultsDb db(dir.path().string()); }).find("is not a plain file"), std::string::npos);
}

TEST(SweepRun, PointsThatDifferOnlyInTimingShareOneMemoryReplay) {
  // A link bandwidth sweep: the baseline's points (and baseline-1tb's,
  // which replays as the baseline) share one memory replay per GPM count;
  // OO-VR's runtime follows the timing, so its played runs differ from the
  // recording and are run in full. The records are those of a sweep that
  // shares nothing, whatever the jobs.
  Sweep s = parse(R"(
scenes = ["crowd"]
schemes = ["baseline", "baseline-1tb", "oo-vr"]
resolutions = ["96x64"]
frames = 4
[sweep]
gpms = [2, 4]
"link.bandwidth" = ["32GBps", "64GBps", "128GBps"]
)");
  resolve_all(s);
  const auto run = [&](unsigned jobs, bool share, std::vector<SweepTask>* tasks) {
    std::vector<RunRecord> records;
    SweepRunOptions o;
    o.jobs = jobs;
    o.share_replays = share;
    o.on_record = [&](const RunRecord& r) { records.push_back(r); };
    o.on_task = [&](const SweepTask& t) {
      if (tasks && t.kind == SweepTask::Kind::point) tasks->push_back(t);
    };
    std::vector<size_t> all(s.points.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    run_points(s, all, o);
    std::sort(records.begin(), records.end(), [](const RunRecord& a, const RunRecord& b) { return a.id < b.id; });
    return records;
  };
  std::vector<SweepTask> none;
  const std::vector<RunRecord> alone = run(1, false, &none);
  ASSERT_EQ(alone.size(), 18u);
  for (const SweepTask& t : none) EXPECT_EQ(t.replay, SharedReplay::Use::none);
  for (unsigned jobs : {1u, 2u}) {
    std::vector<SweepTask> tasks;
    const std::vector<RunRecord> shared = run(jobs, true, &tasks);
    ASSERT_EQ(shared.size(), alone.size());
    for (size_t i = 0; i < alone.size(); ++i) {
      EXPECT_EQ(shared[i].status, "done") << shared[i].error;
      EXPECT_EQ(shared[i].result.dump(), alone[i].result.dump()) << shared[i].scheme << ", " << jobs << " jobs";
      ASSERT_EQ(shared[i].metrics.size(), alone[i].metrics.size());
      for (size_t k = 0; k < alone[i].metrics.size(); ++k) EXPECT_EQ(shared[i].metrics[k].value, alone[i].metrics[k].value);
    }
    // Per GPM count: the baseline's six points (three bandwidths, and
    // baseline-1tb's three) are one recording and five played; OO-VR's
    // three, one recording and two played or run in full (on two GPMs its
    // runtime may send the same work wherever the links are slower; on
    // four, not).
    std::map<std::pair<std::string, SharedReplay::Use>, int> uses;
    for (const SweepTask& t : tasks) {
      const std::string scheme = s.points[t.point].scheme == "oo-vr" ? "oo-vr" : "baseline";
      ++uses[{scheme, t.replay}];
    }
    EXPECT_EQ((uses[{"baseline", SharedReplay::Use::recorded}]), 2) << jobs << " jobs";
    EXPECT_EQ((uses[{"baseline", SharedReplay::Use::played}]), 10) << jobs << " jobs";
    EXPECT_EQ((uses[{"oo-vr", SharedReplay::Use::recorded}]), 2) << jobs << " jobs";
    EXPECT_EQ((uses[{"oo-vr", SharedReplay::Use::mismatched}] + uses[{"oo-vr", SharedReplay::Use::played}]), 4) << jobs;
    EXPECT_GE((uses[{"oo-vr", SharedReplay::Use::mismatched}]), 1) << jobs << " jobs";
  }
}

TEST(SweepRun, PointsRunDoneOrFailedAndTheSameWhateverTheJobs) {
  Sweep s = parse(R"(
scenes = ["crowd", "no-such-scene.obj"]
schemes = ["baseline", "oo-vr"]
resolutions = ["96x64", "64x48"]
frames = 4
[sweep]
gpms = [2, 4]
)");
  resolve_all(s);
  struct Run {
    std::vector<RunRecord> records;
    std::vector<SweepTask> tasks;
    std::vector<std::string> status;
  };
  const auto run = [&](unsigned jobs) {
    Run out;
    SweepRunOptions o;
    o.jobs = jobs;
    o.use_cache = false;
    o.on_record = [&](const RunRecord& r) { out.records.push_back(r); };
    o.on_task = [&](const SweepTask& t) { out.tasks.push_back(t); };
    o.on_status = [&](const std::string& line) { out.status.push_back(line); };
    std::vector<size_t> all(s.points.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    run_points(s, all, o);
    std::sort(out.records.begin(), out.records.end(), [](const RunRecord& a, const RunRecord& b) { return a.id < b.id; });
    return out;
  };
  const Run one = run(1);
  for (unsigned jobs : {2u, 5u}) {
    const Run many = run(jobs);
    ASSERT_EQ(many.records.size(), one.records.size());
    for (size_t i = 0; i < one.records.size(); ++i) {
      EXPECT_EQ(many.records[i].status, one.records[i].status);
      EXPECT_EQ(many.records[i].result.dump(), one.records[i].result.dump()) << jobs << " jobs";
      ASSERT_EQ(many.records[i].metrics.size(), one.records[i].metrics.size());
      for (size_t k = 0; k < one.records[i].metrics.size(); ++k)
        EXPECT_EQ(many.records[i].metrics[k].value, one.records[i].metrics[k].value);
    }
    // Each group loads once, each scene once (its two groups share it, the
    // missing one's failure too), each point runs once, after its group's
    // load; no more than two groups are held at once.
    EXPECT_EQ(std::count(many.status.begin(), many.status.end(), "loading crowd"), 1) << jobs << " jobs";
    EXPECT_EQ(std::count(many.status.begin(), many.status.end(), "loading no-such-scene.obj"), 1) << jobs << " jobs";
    std::map<size_t, SweepTask> loads;
    std::map<size_t, double> group_end;
    size_t points = 0;
    for (const SweepTask& t : many.tasks) {
      EXPECT_LT(t.worker, jobs);
      EXPECT_LE(t.start_s, t.end_s);
      if (t.kind == SweepTask::Kind::load) {
        EXPECT_TRUE(loads.emplace(t.group, t).second) << "group " << t.group;
      } else {
        ++points;
      }
      group_end[t.group] = std::max(group_end[t.group], t.end_s);
    }
    EXPECT_EQ(loads.size(), 4u);
    EXPECT_EQ(points, 8u);  // the missing scene's points do not run
    for (const SweepTask& t : many.tasks)
      if (t.kind == SweepTask::Kind::point) {
        EXPECT_GE(t.start_s, loads.at(t.group).end_s);
      }
    for (const auto& [g, l] : loads) {
      size_t held = 0;
      for (const auto& [h, m] : loads) held += m.start_s <= l.start_s && group_end[h] > l.start_s;
      EXPECT_LE(held, 2u) << "when group " << g << " began loading";
    }
  }
  ASSERT_EQ(one.records.size(), 16u);
  size_t failed = 0;
  for (const RunRecord& r : one.records) {
    if (r.status == "failed") {
      ++failed;
      EXPECT_EQ(r.scene, "no-such-scene.obj");
      EXPECT_NE(r.error.find("no-such-scene.obj"), std::string::npos);
      continue;
    }
    EXPECT_EQ(r.status, "done");
    const auto has = [&](const std::string& location, const std::string& metric) {
      return std::any_of(r.metrics.begin(), r.metrics.end(),
                         [&](const Metric& m) { return m.location == location && m.metric == metric; });
    };
    EXPECT_TRUE(has("frame", "latency"));
    EXPECT_TRUE(has("l2", "served_share"));
    EXPECT_TRUE(has("link[0->1]", "utilisation"));
    EXPECT_TRUE(has("gpm[1]->gpm[0]", "bytes"));
    EXPECT_TRUE(has("gpm[1].dram", "bytes"));
    if (r.scheme == "oo-vr") {
      EXPECT_TRUE(has("oo-vr", "batches"));
      EXPECT_TRUE(has("oo-vr", "moved_chunks"));
      EXPECT_TRUE(has("oo-vr", "predictor.c2"));
    }
  }
  EXPECT_EQ(failed, 8u);
}

// Every point of `s` (resolved here), run without the trace cache; the
// records in the order they ended.
std::vector<RunRecord> run_all(Sweep& s) {
  resolve_all(s);
  std::vector<RunRecord> out;
  SweepRunOptions o;
  o.use_cache = false;
  o.on_record = [&](const RunRecord& r) { out.push_back(r); };
  std::vector<size_t> all(s.points.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  run_points(s, all, o);
  return out;
}

// A database written before version 3 hashed every key read into a run's
// id, other schemes' own too (OO-VR's oo.* into a baseline run's). Opened to
// write, it is migrated: each run keeps the keys its scheme reads and its
// id follows, metrics and images with it, so `--resume` runs nothing. A run
// record of version 2 (a SLURM task's) reads back the same way.
TEST(ResultsDb, AVersion2DatabaseIsMigratedSoResumeRunsNothing) {
  Sweep s = parse("scenes = ['crowd']\nschemes = ['baseline', 'oo-vr']\nresolutions = ['96x64']\nframes = 1\n");
  const std::vector<RunRecord> records = run_all(s);
  ASSERT_EQ(records.size(), 2u);
  const nlohmann::ordered_json every_key = to_json(s.points[1].machine.entries);
  ASSERT_TRUE(every_key.contains("oo.tsl_threshold"));
  test::TempDir dir;
  const std::string path = dir.file("old.db");
  std::set<std::string> old_ids;
  {
    ResultsDb db(path);
    begin_sweep(s, plan_sweep(s, db, false, false), db, "oovr sweep t.toml");
    for (RunRecord r : records) {
      for (const auto& [key, e] : every_key.items())  // as version 2 wrote it
        if (!r.config.contains(key)) r.config[key] = e;
      r.id = stable_id(canonical_setup(r));
      old_ids.insert(r.id);
      ASSERT_TRUE(db.insert(r));
      if (r.scheme == "baseline") {
        nlohmann::ordered_json j = to_json(r);
        j["schema_version"] = 2;
        EXPECT_EQ(run_record_from_json(j).id, s.points[0].id);
        EXPECT_FALSE(run_record_from_json(j).config.contains("oo.tsl_threshold"));
      }
    }
    EXPECT_FALSE(plan_sweep(s, db, true, false).todo.empty());  // as written now, nothing matches
  }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(raw, "PRAGMA user_version = 2", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(raw);
  ResultsDb db(path);  // opened to write: migrated
  db.verify();
  std::set<std::string> ids;
  for (const auto& [id, status] : db.run_status()) ids.insert(id);
  EXPECT_EQ(ids, (std::set<std::string>{s.points[0].id, s.points[1].id}));
  EXPECT_NE(ids, old_ids);
  EXPECT_TRUE(plan_sweep(s, db, true, false).todo.empty());
  for (const RunRecord& r : db.runs()) {
    EXPECT_GT(r.metrics.size(), 30u) << r.scheme;
    EXPECT_EQ(r.config.contains("oo.tsl_threshold"), r.scheme == "oo-vr") << r.scheme;
    EXPECT_FALSE(r.config.contains("test_added.knob")) << r.scheme;
  }
}

TEST(SweepRun, AStoredResultReadsBackExactly) {
  Sweep s = parse("scenes = ['crowd']\nschemes = ['oo-vr', 'afr']\nresolutions = ['96x64']\n");
  const std::vector<RunRecord> out = run_all(s);
  ASSERT_EQ(out.size(), 2u);
  for (const RunRecord& r : out) {
    ASSERT_EQ(r.status, "done") << r.error;
    // Each figure is stored once: the statistics are the metrics rows, the
    // result the rest.
    EXPECT_FALSE(r.result.contains("stats")) << r.scheme;
    EXPECT_FALSE(r.result.contains("memory")) << r.scheme;
    const SchemeResult back = scheme_result_from_stored(r.result, r.metrics);
    // Everything comes back: writing it again gives the same text and the
    // same rows, in the same order.
    EXPECT_EQ(stored_result_json(back).dump(), r.result.dump()) << r.scheme;
    const std::vector<Metric> rows = metrics_of(back);
    ASSERT_EQ(rows.size(), r.metrics.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      EXPECT_EQ(rows[i].location, r.metrics[i].location);
      EXPECT_EQ(rows[i].metric, r.metrics[i].metric);
      EXPECT_EQ(rows[i].value, r.metrics[i].value) << rows[i].location << " " << rows[i].metric;
      EXPECT_EQ(rows[i].unit, r.metrics[i].unit);
    }
    EXPECT_EQ(back.frame_latency_s, r.result["frame_latency_s"].get<double>());
    EXPECT_GT(back.best_to_worst(), 0);
    // A result that carries its statistics (as databases before version 4
    // stored it) reads back from itself, whatever the rows.
    const nlohmann::ordered_json whole = to_json(back);
    EXPECT_EQ(to_json(scheme_result_from_stored(whole, {})).dump(), whole.dump()) << r.scheme;
    // A result written before results carried their statistics ("stats")
    // reads back from its memory section and scheme figures: the same
    // document, and the rows it gave then, each as today's.
    nlohmann::ordered_json old = whole;
    old.erase("stats");
    old.erase("energy_j");  // results without statistics came before energy
    const SchemeResult legacy = scheme_result_from_json(old);
    nlohmann::ordered_json again = to_json(legacy);
    again.erase("stats");
    EXPECT_EQ(again.dump(), old.dump()) << r.scheme;
    std::map<std::pair<std::string, std::string>, double> today;
    for (const Metric& m : metrics_of(back)) today[{m.location, m.metric}] = m.value;
    const std::vector<Metric> then = metrics_of(legacy);
    EXPECT_GT(then.size(), 30u);
    EXPECT_LT(then.size(), today.size());  // without the engine's statistics
    for (const Metric& m : then) {
      const auto it = today.find({m.location, m.metric});
      ASSERT_NE(it, today.end()) << m.location << " " << m.metric;
      EXPECT_EQ(it->second, m.value) << m.location << " " << m.metric;
    }
  }
  EXPECT_NE(message_of([] {
              (void)scheme_result_from_json(nlohmann::ordered_json{{"scheme", "x"}});
            }).find("not oovr's"),
            std::string::npos);

  // Through a database: the rows come back in the order they were written,
  // and with them the run, exactly.
  test::TempDir dir;
  const std::string path = dir.file("r.db");
  {
    ResultsDb db(path);
    begin_sweep(s, plan_sweep(s, db, false, false), db, "oovr sweep t.toml");
    for (const RunRecord& r : out) ASSERT_TRUE(db.insert(r));
  }
  const auto same_run = [&](const std::vector<RunRecord>& stored) {
    ASSERT_EQ(stored.size(), out.size());
    for (const RunRecord& x : stored) {
      const RunRecord& r = x.id == out[0].id ? out[0] : out[1];
      ASSERT_EQ(x.id, r.id);
      EXPECT_EQ(to_json(scheme_result_from_stored(x.result, x.metrics)).dump(),
                to_json(scheme_result_from_stored(r.result, r.metrics)).dump())
          << r.scheme;
    }
  };
  {
    ResultsDb db(path);
    db.verify();
    const auto stored = db.runs();
    same_run(stored);
    for (const RunRecord& x : stored) {
      const RunRecord& r = x.id == out[0].id ? out[0] : out[1];
      ASSERT_EQ(x.metrics.size(), r.metrics.size());
      for (size_t i = 0; i < x.metrics.size(); ++i)
        EXPECT_EQ(x.metrics[i].location + " " + x.metrics[i].metric, r.metrics[i].location + " " + r.metrics[i].metric);
    }
  }
  // A version 3 database (whole results, rows without their order) reads
  // the same, opened to read, and to write once migrated.
  {
    ResultsDb db(path);
    for (const RunRecord& r : out) db.remove(r.id);
    for (RunRecord r : out) {
      r.result = to_json(scheme_result_from_stored(r.result, r.metrics));
      ASSERT_TRUE(db.insert(r));
    }
  }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(raw, "ALTER TABLE metrics DROP COLUMN ordinal; PRAGMA user_version = 3", nullptr, nullptr, nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(raw);
  sqlite3_close(raw);
  same_run(ResultsDb(path, ResultsDb::Access::read_only).runs());
  ResultsDb migrated(path);
  migrated.verify();
  same_run(migrated.runs());
}

}  // namespace
}  // namespace oovr

namespace oovr {
namespace {

// What oovr checks of the executable the nodes will run, before it writes
// anything: this process's own passes; a relative path, a missing file (a
// build removed or replaced while oovr ran), a folder and a file that is
// not executable are refused, naming it.
TEST(Sweep, SlurmSubmitsOnlyAnExecutableThatIsThere) {
  EXPECT_NO_THROW(check_slurm_executable(this_executable()));
  test::TempDir dir;
  const std::string plain = dir.file("plain", "#!/bin/sh\n");
  std::filesystem::permissions(plain, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  const std::string runnable = dir.file("runnable", "#!/bin/sh\n");
  std::filesystem::permissions(runnable, std::filesystem::perms::owner_all);
  EXPECT_NO_THROW(check_slurm_executable(runnable));
  for (const auto& [exe, says] : {std::pair<std::string, std::string>{"build/oovr", "not an absolute path"},
                                  {dir.file("gone"), "is not a file here"},
                                  {dir.path().string(), "is not a file here"},
                                  {plain, "is not executable"}}) {
    const std::string path = exe;  // (Clang 14 cannot capture a structured binding.)
    const std::string why = message_of([&] { check_slurm_executable(path); });
    EXPECT_NE(why.find(says), std::string::npos) << exe << ": " << why;
    EXPECT_NE(why.find(exe), std::string::npos) << why;
  }
}

TEST(Sweep, SlurmTasksRunATraceGroupEachByDefault) {
  // 2 scenes x 2 resolutions x 3 schemes: 4 trace groups of 3 points, the
  // schemes innermost.
  Sweep s = parse_sweep(
      "scenes = ['crowd', 'courtyard']\nschemes = ['baseline', 'oo-vr', 'sfr-v']\nresolutions = ['64x32', '96x64']\nframes = "
      "1\n",
      "t.toml", "");
  resolve_all(s);
  std::vector<size_t> todo(s.points.size());
  for (size_t i = 0; i < todo.size(); ++i) todo[i] = i;
  const auto tasks = slurm_tasks(s, todo, 0);
  ASSERT_EQ(tasks.size(), 4u);
  for (const auto& t : tasks) {
    ASSERT_EQ(t.size(), 3u);
    for (size_t i : t) EXPECT_EQ(trace_group(s.points[i]), trace_group(s.points[t.front()]));
  }
  // Only some points left: still one task per group they come from, in order.
  const auto part = slurm_tasks(s, {1, 2, 9, 10}, 0);
  EXPECT_EQ(part, (std::vector<std::vector<size_t>>{{1, 2}, {9, 10}}));
  // --chunk: consecutive points, whatever their groups.
  EXPECT_EQ(slurm_tasks(s, {1, 2, 9, 10}, 3), (std::vector<std::vector<size_t>>{{1, 2, 9}, {10}}));
  // More groups than kMaxTasks: consecutive groups share a task (each
  // group whole in one), and there are at most kMaxTasks of them. 1,200
  // groups of 2 points: 600 tasks of 2 groups.
  Sweep many;
  many.points.resize(2400);
  std::vector<size_t> all(many.points.size());
  for (size_t k = 0; k < all.size(); ++k) {
    many.points[k].scene = "scene" + std::to_string(k / 2);
    all[k] = k;
  }
  const auto shared = slurm_tasks(many, all, 0);
  ASSERT_EQ(shared.size(), 600u);
  for (size_t t = 0; t < shared.size(); ++t) EXPECT_EQ(shared[t], (std::vector<size_t>{4 * t, 4 * t + 1, 4 * t + 2, 4 * t + 3}));
}

}  // namespace
}  // namespace oovr
