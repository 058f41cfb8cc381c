// Units, the strict configuration tree, and every preset in configs/.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "oovr/core/config.h"
#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/memory/memory_system.h"
#include "oovr/timing/gpm_model.h"
#include "test_util.h"

namespace oovr {
namespace {

using test::message_of;

TEST(Units, ParseWithUnits) {
  EXPECT_EQ(parse_bytes("128B", "k").value, 128u);
  EXPECT_EQ(parse_bytes("128KB", "k").value, 128u * 1024);
  EXPECT_EQ(parse_bytes("1 MiB", "k").value, 1u << 20);
  EXPECT_EQ(parse_bytes("4GB", "k").value, 4ull << 30);
  EXPECT_DOUBLE_EQ(parse_bandwidth("64GBps", "k").value, 64e9);
  EXPECT_DOUBLE_EQ(parse_bandwidth("64 GB/s", "k").value, 64e9);
  EXPECT_DOUBLE_EQ(parse_bandwidth("1TBps", "k").value, 1e12);
  EXPECT_DOUBLE_EQ(parse_time("100ns", "k").value, 100e-9);
  EXPECT_DOUBLE_EQ(parse_frequency("1GHz", "k").value, 1e9);
  EXPECT_NE(message_of([] { parse_bytes("12 parsecs", "cache.l2.size"); }).find("cache.l2.size"), std::string::npos);
  EXPECT_THROW(parse_bytes("1.5B", "k"), Error);
  EXPECT_THROW(parse_bytes("-4KB", "k"), Error);
  EXPECT_THROW(parse_bandwidth("fast", "k"), Error);
  EXPECT_EQ(format_bytes({128 << 10}), "128 KB");
  EXPECT_EQ(format_bandwidth({64e9}), "64 GB/s");
}

// Whatever oovr prints as a value, it reads back as the same value (oovr
// config once printed "124.9 KB", which --config then refused).
TEST(Units, PrintedValuesReadBack) {
  for (const uint64_t b : {0ull, 1ull, 1000ull, 127897ull, 128ull << 10, 1536ull << 10, 3ull << 30, (3ull << 30) + 1})
    EXPECT_EQ(parse_bytes(format_bytes({b}), "k").value, b) << format_bytes({b});
  EXPECT_EQ(format_bytes({1536 << 10}), "1536 KB");
  EXPECT_EQ(format_bytes({127897}), "127897 B");
  for (const double bw : {64e9, 1e12, 1.5e12, 123456789.0, 0.1e9 + 1, 900e6, 1e16})
    EXPECT_EQ(parse_bandwidth(format_bandwidth({bw}), "k").value, bw) << format_bandwidth({bw});
  // A time or frequency goes through the configuration: set, resolved
  // (printed), set again from the printed form.
  const auto reads_back = [](const std::string& text, double (*get)(const Config&)) {
    Config c;
    c.set("x", text);
    const double v = get(c);
    Config back;
    back.set("x", c.resolved().at("x"));
    EXPECT_EQ(get(back), v) << text << " printed as " << c.resolved().at("x");
  };
  for (const std::string t : {"100ns", "82ns", "1.3us", "0.1ns", "1ms", "7e-10s"})
    reads_back(t, [](const Config& c) { return c.get_time("x", {0}).value; });
  for (const std::string f : {"1GHz", "1.3GHz", "1234567Hz", "999.9999MHz"})
    reads_back(f, [](const Config& c) { return c.get_frequency("x", {0}).value; });
}

TEST(Config, TomlTablesBecomeDottedKeys) {
  const Config c = Config::from_toml_string("gpms = 8\n[link]\nbandwidth = \"128GBps\"\n[cache.l2]\nways = 8\n", "t.toml");
  EXPECT_EQ(c.get_int("gpms", 4, 1, 32), 8);
  EXPECT_DOUBLE_EQ(c.get_bandwidth("link.bandwidth", {1}).value, 128e9);
  EXPECT_EQ(c.get_int("cache.l2.ways", 16, 1, 1024), 8);
  EXPECT_EQ(c.get_int("absent", 42, 0, 100), 42);
  EXPECT_NO_THROW(c.check_all_used());
  EXPECT_EQ(c.resolved().at("absent"), "42") << "defaults are part of the resolved configuration";
}

TEST(Config, OverridesOnTheCommandLine) {
  Config c = Config::from_toml_string("gpms = 4\n[link]\nbandwidth = \"64GBps\"\n", "t.toml");
  c.set("link.bandwidth=128GBps");
  c.set("gpms=8");
  EXPECT_EQ(c.get_int("gpms", 4, 1, 32), 8);
  EXPECT_DOUBLE_EQ(c.get_bandwidth("link.bandwidth", {1}).value, 128e9);
  EXPECT_THROW(c.set("novalue"), Error);
  EXPECT_THROW(c.set("=5"), Error);
  EXPECT_THROW(c.set("gpms="), Error);
  EXPECT_THROW(c.set("bad key=1"), Error);
}

TEST(Config, UnknownKeysAreErrorsNamingThem) {
  Config c = Config::from_toml_string("gpms = 4\n[link]\nbandwdith = \"64GBps\"\n", "t.toml");
  c.set("cache.l3.size=8MB");
  (void)MemorySpec::from_config(c);
  const std::string m = message_of([&] { c.check_all_used(); });
  EXPECT_NE(m.find("link.bandwdith"), std::string::npos) << m;
  EXPECT_NE(m.find("t.toml:3"), std::string::npos) << m;
  EXPECT_NE(m.find("cache.l3.size"), std::string::npos) << m;
  EXPECT_THROW(c.check_all_used(), UnknownKeyError) << "its own kind: the Python module's KeyError";
  EXPECT_THROW(Config::from_toml_file("/no/such/preset.toml"), NotFoundError);
}

TEST(Config, IllTypedValuesAreErrorsNamingTheKey) {
  const auto spec_error = [](const std::string& assignment) {
    Config c;
    c.set(assignment);
    return message_of([&] { (void)MemorySpec::from_config(c); });
  };
  EXPECT_NE(spec_error("gpms=four").find("'gpms'"), std::string::npos);
  EXPECT_NE(spec_error("gpms=1.5").find("'gpms'"), std::string::npos);
  EXPECT_NE(spec_error("gpms=0").find("'gpms'"), std::string::npos);
  EXPECT_NE(spec_error("link.bandwidth=64").find("'link.bandwidth'"), std::string::npos);
  EXPECT_NE(spec_error("link.bandwidth=64GB").find("'link.bandwidth'"), std::string::npos);
  EXPECT_NE(spec_error("cache.l2.size=1000B").find("'cache.l2.size'"), std::string::npos);
  EXPECT_NE(spec_error("cache.l2.replacement=oracle").find("'cache.l2.replacement'"), std::string::npos);
  EXPECT_NE(spec_error("memory.placement=everywhere").find("first-touch"), std::string::npos) << "names the choices";
  EXPECT_NE(spec_error("link.topology=mesh").find("'link.topology'"), std::string::npos);
  EXPECT_NE(spec_error("cache.remote.invalidate=sometimes").find("draw, frame, never"), std::string::npos);
  EXPECT_NE(spec_error("memory.line=100B").find("'memory.line'"), std::string::npos);
  EXPECT_NE(message_of([] { Config::from_toml_string("gpms = [1, 2]\n", "t.toml"); }).find("'gpms'"), std::string::npos);
  EXPECT_NE(message_of([] { Config::from_toml_string("gpms = \n", "bad.toml"); }).find("bad.toml"), std::string::npos);
  EXPECT_THROW(Config::from_toml_file("/no/such/file.toml"), Error);
}

// Values are checked in the type they are used in: nothing is truncated,
// nothing non-finite or out of its physical range gets through.
TEST(Config, ValuesAreCheckedBeforeTheyAreNarrowed) {
  const auto spec_error = [](const std::string& assignment) {
    Config c;
    c.set(assignment);
    return message_of([&] {
      (void)MemorySpec::from_config(c);
      (void)TimingSpec::from_config(c);
    });
  };
  // 4294967297 once became 1 GPM (2^32 + 1 truncated to int).
  EXPECT_NE(spec_error("gpms=4294967297").find("'gpms' (--set) must be a whole number from 1 to 32"), std::string::npos);
  EXPECT_NE(spec_error("cache.l1.ways=4294967300").find("'cache.l1.ways'"), std::string::npos);
  EXPECT_NE(spec_error("gpm.sms=-4294967288").find("'gpm.sms'"), std::string::npos);
  EXPECT_NE(spec_error("gpm.draws_ahead=9223372036854775807").find("'gpm.draws_ahead'"), std::string::npos);
  EXPECT_NE(spec_error("gpm.draw_cycles=nan").find("'gpm.draw_cycles'"), std::string::npos);
  EXPECT_NE(spec_error("gpm.draw_cycles=inf").find("'gpm.draw_cycles'"), std::string::npos);
  EXPECT_NE(spec_error("link.latency=1e300s").find("'link.latency'"), std::string::npos);
  EXPECT_NE(spec_error("frequency=1e-300Hz").find("'frequency'"), std::string::npos);
  EXPECT_NE(spec_error("frequency=1e300Hz").find("'frequency'"), std::string::npos);
  EXPECT_NE(spec_error("link.bandwidth=1e-300Bps").find("'link.bandwidth'"), std::string::npos);
  EXPECT_NE(spec_error("dram.bandwidth=1e300Bps").find("'dram.bandwidth'"), std::string::npos);
  EXPECT_NE(spec_error("cache.l1.size=1e300B").find("'cache.l1.size'"), std::string::npos);
  // Every L1 holds a tag per line: 1 GB each once ran out of memory.
  EXPECT_NE(spec_error("cache.l1.size=1GB").find("'cache.l1.size' must be at most 16 MB"), std::string::npos);
  EXPECT_NE(spec_error("cache.l2.size=512MB").find("'cache.l2.size' must be at most 256 MB"), std::string::npos);
  EXPECT_EQ(spec_error("gpms=8"), "<no error>");
  // The same checks from a file.
  const auto file_error = [](const std::string& text) {
    return message_of([&] {
      const Config c = Config::from_toml_string(text, "t.toml");
      (void)MemorySpec::from_config(c);
      (void)TimingSpec::from_config(c);
    });
  };
  EXPECT_NE(file_error("gpms = 4294967297\n").find("'gpms'"), std::string::npos);
  EXPECT_NE(file_error("[gpm]\ndraw_cycles = nan\n").find("finite"), std::string::npos);
  EXPECT_NE(file_error("[gpm]\ndraw_cycles = -inf\n").find("finite"), std::string::npos);
}

// A configuration file is read only when it is a regular file of bounded
// size and shape.
TEST(Config, FilesAreReadOnlyWhenTheyAreRegularAndBounded) {
  EXPECT_NE(message_of([] { Config::from_toml_file(""); }).find("empty"), std::string::npos);
  EXPECT_NE(message_of([] { Config::from_toml_file("/tmp"); }).find("directory"), std::string::npos);
  EXPECT_NE(message_of([] { Config::from_toml_file("/dev/zero"); }).find("not a regular file"), std::string::npos);
  const std::string fifo = std::filesystem::temp_directory_path() / ("oovr-test-fifo-" + std::to_string(::getpid()));
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(message_of([&] { Config::from_toml_file(fifo); }).find("not a regular file"), std::string::npos);
  std::filesystem::remove(fifo);
  std::string deep = "[";
  for (int i = 0; i < 20000; ++i) deep += i ? ".a" : "a";
  deep += "]\nx = 1\n";
  EXPECT_NE(message_of([&] { Config::from_toml_string(deep, "deep.toml"); }).find("dotted parts"), std::string::npos);
  std::string dotted;
  for (int i = 0; i < 20000; ++i) dotted += i ? ".a" : "a";
  EXPECT_NE(message_of([&] { Config::from_toml_string(dotted + " = 1\n", "deep.toml"); }).find("dotted parts"),
            std::string::npos);
  // After an empty inline table, later lines' keys are still counted (the
  // check lost track of them and toml++ overflowed its stack).
  EXPECT_NE(
      message_of([&] { Config::from_toml_string("x = {}\ny = 1\n" + dotted + " = 1\n", "deep.toml"); }).find("dotted parts"),
      std::string::npos);
  std::string inl = "x = ";
  for (int i = 0; i < 20000; ++i) inl += "{a = ";
  EXPECT_NE(
      message_of([&] { Config::from_toml_string(inl + "1" + std::string(20000, '}') + "\n", "deep.toml"); }).find("deep.toml"),
      std::string::npos);
  // Dots in values and strings are not key parts.
  std::string many = "x = [";
  for (int i = 0; i < 100; ++i) many += "1.5, ";
  many += "2.5]\ny = \"a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q.r.s.t.u.v.w.x.y.z.a.b.c.d.e.f.g.h\"\n";
  EXPECT_EQ(message_of([&] { Config::from_toml_string(many, "many.toml"); }).find("dotted parts"), std::string::npos);
  EXPECT_NE(message_of([] { Config::from_toml_string(std::string((1 << 20) + 1, ' '), "big.toml"); }).find("MiB"),
            std::string::npos);
}

// `oovr config --all` and every result describe each key: value, default,
// where the value came from, what the key takes, and the value in base units.
TEST(Config, EveryKeyReadIsDescribed) {
  Config c;
  c.set("gpms=8");
  c.set("cache.l1.size=256KB");
  check_config(c);
  const auto& e = c.entries();
  ASSERT_EQ(e.size(), c.resolved().size());
  const Config::Entry& gpms = e.at("gpms");
  EXPECT_EQ(gpms.value, "8");
  EXPECT_EQ(gpms.fallback, "4");
  EXPECT_EQ(gpms.source, "--set");
  EXPECT_EQ(gpms.kind, "a whole number from 1 to 32");
  EXPECT_EQ(gpms.base, 8.0);
  const Config::Entry& l1 = e.at("cache.l1.size");
  EXPECT_EQ(l1.value, "256 KB");
  EXPECT_EQ(l1.fallback, "128 KB");
  EXPECT_EQ(l1.unit, "B");
  EXPECT_EQ(l1.base, 262144.0);
  const Config::Entry& link = e.at("link.bandwidth");
  EXPECT_EQ(link.source, "default");
  EXPECT_EQ(link.unit, "B/s");
  EXPECT_EQ(link.base, 64e9);
  EXPECT_EQ(e.at("link.latency").unit, "s");
  EXPECT_EQ(e.at("frequency").unit, "Hz");
  EXPECT_EQ(e.at("memory.placement").kind.rfind("one of first-touch, ", 0), 0u) << e.at("memory.placement").kind;
  EXPECT_FALSE(e.at("memory.placement").base.has_value());
  for (const auto& [key, entry] : e) {
    EXPECT_FALSE(entry.value.empty()) << key;
    EXPECT_FALSE(entry.kind.empty()) << key;
    EXPECT_EQ(entry.value, c.resolved().at(key)) << key;
    EXPECT_EQ(entry.base.has_value(),
              !entry.unit.empty() || entry.kind.rfind("a whole", 0) == 0 || entry.kind.rfind("a number", 0) == 0)
        << key;
  }
  const Config file = Config::from_toml_string("gpms = 2\n", "preset.toml");
  check_config(file);
  EXPECT_EQ(file.entries().at("gpms").source, "preset.toml:1");
}

TEST(Config, EveryPresetLoads) {
  const std::filesystem::path dir = std::filesystem::path(OOVR_SOURCE_DIR) / "configs";
  int presets = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".toml") continue;
    SCOPED_TRACE(e.path().filename().string());
    const Config c = Config::from_toml_file(e.path().string());
    const MemorySpec spec = MemorySpec::from_config(c);
    EXPECT_NO_THROW(check_config(c));
    AddressMap map(spec.page, spec.line);
    map.add("buffer", Category::texture, 1 << 20);
    MemorySystem mem(spec, map);
    EXPECT_EQ(mem.topology().gpms(), spec.gpms);
    ++presets;
  }
  EXPECT_GE(presets, 4);
}

TEST(Config, TheTable1PresetIsTheDefault) {
  // The code's defaults and configs/paper-table1.toml must not drift apart.
  const Config preset = Config::from_toml_file(std::string(OOVR_SOURCE_DIR) + "/configs/paper-table1.toml");
  const Config empty;
  check_config(preset);
  check_config(empty);
  EXPECT_EQ(preset.resolved(), empty.resolved());
}

}  // namespace
}  // namespace oovr
