// Units, the strict configuration tree, and every preset in configs/.
#include <gtest/gtest.h>

#include <filesystem>

#include "oovr/core/config.h"
#include "oovr/core/error.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/timing/gpm_model.h"
#include "oovr/core/config_sections.h"
#include "oovr/memory/memory_system.h"

namespace oovr {
namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

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

TEST(Config, TomlTablesBecomeDottedKeys) {
  const Config c = Config::from_toml_string("gpms = 8\n[link]\nbandwidth = \"128GBps\"\n[cache.l2]\nways = 8\n", "t.toml");
  EXPECT_EQ(c.get_int("gpms", 4), 8);
  EXPECT_DOUBLE_EQ(c.get_bandwidth("link.bandwidth", {1}).value, 128e9);
  EXPECT_EQ(c.get_int("cache.l2.ways", 16), 8);
  EXPECT_EQ(c.get_int("absent", 42), 42);
  EXPECT_NO_THROW(c.check_all_used());
  EXPECT_EQ(c.resolved().at("absent"), "42") << "defaults are part of the resolved configuration";
}

TEST(Config, OverridesOnTheCommandLine) {
  Config c = Config::from_toml_string("gpms = 4\n[link]\nbandwidth = \"64GBps\"\n", "t.toml");
  c.set("link.bandwidth=128GBps");
  c.set("gpms=8");
  EXPECT_EQ(c.get_int("gpms", 4), 8);
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
