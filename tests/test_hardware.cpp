// Hardware data and the correlation statistics (experiments/hardware.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/experiments/hardware.h"

namespace oovr {
namespace {

// The lines that say what the GPU drew (every data file has them).
const std::string kWorkload = "commit,ca88d23\nmaterials,one-pass\ntexture_format,rgba8\naniso,16\n";
const std::string kHeader = "scene,resolution,frame,full_us,geom_us,left_us,draws,triangles\n";

std::string message(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Hardware, PearsonOnKnownSeries) {
  EXPECT_DOUBLE_EQ(pearson({1, 2, 3}, {2, 4, 6}), 1.0);
  EXPECT_DOUBLE_EQ(pearson({1, 2, 3}, {6, 4, 2}), -1.0);
  // x = 1..4, y = 1, 3, 2, 4: co-deviation 4, deviations 5 and 5: r = 4/5.
  EXPECT_NEAR(pearson({1, 2, 3, 4}, {1, 3, 2, 4}), 0.8, 1e-12);
  EXPECT_EQ(pearson({1, 1, 1}, {1, 2, 3}), 0.0) << "a constant series correlates with nothing";
  EXPECT_EQ(pearson({1}, {1}), 0.0);
}

TEST(Hardware, ReadsTheCsvAndWritesItBack) {
  const std::string text = "renderer,Some GPU/PCIe\n" + kWorkload + kHeader +
                           "courtyard,640x480,0,115.500,47.700,60.100,61,23288\n"
                           "courtyard,1280x1024,3,377.900,47.400,191.100,61,23288\n";
  const HardwareData d = HardwareData::parse(text, "t.csv");
  EXPECT_EQ(d.renderer, "Some GPU/PCIe");
  ASSERT_EQ(d.frames.size(), 2u);
  EXPECT_EQ(d.frames[1].resolution, "1280x1024");
  EXPECT_EQ(d.frames[1].frame, 3);
  EXPECT_DOUBLE_EQ(d.frames[0].full_us, 115.5);
  EXPECT_EQ(d.frames[0].draws, 61u);
  EXPECT_EQ(d.workload.commit, "ca88d23");
  EXPECT_EQ(d.workload.materials, "one-pass");
  EXPECT_EQ(d.workload.texture_format, "rgba8");
  EXPECT_EQ(d.workload.aniso, 16);
  EXPECT_EQ(d.csv(), text);
  const HardwareData back = HardwareData::parse(d.csv(), "again");
  EXPECT_EQ(back.workload.materials, "one-pass");
  EXPECT_EQ(back.frames[1].full_us, 377.9);
}

TEST(Hardware, DataThatDoNotSayWhatWasDrawnAreRefused) {
  for (const char* key : {"commit", "materials", "texture_format", "aniso"}) {
    std::string lines;
    for (const std::string& l : split_fields(kWorkload, '\n'))
      if (!l.empty() && l.rfind(key, 0) != 0) lines += l + "\n";
    const std::string m =
        message([&] { (void)HardwareData::parse(lines + kHeader + "courtyard,64x64,0,10,1,5,61,23288\n", "w.csv"); });
    EXPECT_EQ(m, "hardware data 'w.csv' line 4: the data do not say what the GPU drew: no '" + std::string(key) +
                     "' line before the header (docs/data/hardware/README.md)")
        << key;
  }
  const auto with = [&](const std::string& line) {
    return message([&] { (void)HardwareData::parse(line + "\n" + kWorkload + kHeader + "c,64x64,0,1,1,1,1,1\n", "w.csv"); });
  };
  EXPECT_EQ(with("materials,shiny"), "hardware data 'w.csv' line 1: 'materials' is real or one-pass, not 'shiny'");
  EXPECT_EQ(
      with("commit,xyz"),
      "hardware data 'w.csv' line 1: 'commit' is oovr's commit (7 to 40 hex digits, -dirty after them) or unknown, not 'xyz'");
  EXPECT_EQ(with("aniso,32"), "hardware data 'w.csv' line 1: 'aniso' is a whole number from 1 to 16, not '32'");
  EXPECT_NE(with("texture_format,dxt9").find("unknown texture format 'dxt9'"), std::string::npos);
  EXPECT_EQ(with("commit,ca88d23"), "hardware data 'w.csv' line 2: a second 'commit' line");
  EXPECT_EQ(with("renderer,\x1b[31mred"), "hardware data 'w.csv' line 1: 'renderer' needs a value of printable text");
  EXPECT_EQ(with("aniso,4,5"), "hardware data 'w.csv' line 1: 'aniso' line has 3 fields, not 2");
}

// oovr correlate simulates the workload the GPU drew, and refuses a scene
// that is no longer it: one error naming the scene, the draws and
// triangles measured and those found.
TEST(Hardware, AScenesThatChangedSinceItWasMeasuredIsRefused) {
  const HardwareData d = HardwareData::parse(kWorkload + kHeader +
                                                 "courtyard,64x64,0,10,1,5,60,23288\n"
                                                 "courtyard,128x96,0,11,1,5,60,23288\n",
                                             "old.csv");
  EXPECT_EQ(message([&] { (void)correlate(d, {}); }),
            "scene 'courtyard' is not the workload the GPU drew: the data were measured with 60 draws and 23288 triangles "
            "(oovr ca88d23, one-pass materials), oovr's scene has 61 draws and 23288 triangles; measure it again "
            "(oovr-reference --time) or name the scene as it was drawn");
}

// Leave one scene out, worked by hand: two values of a key, three scenes of
// one point each. At value "a" the ratios are 1, 1, 4; at "b" 1, 2, 2.
TEST(Hardware, LeaveOneSceneOutFitsOnTheOthersAndTestsTheOneLeftOut) {
  const auto run = [](std::vector<double> ratios) {
    Correlation c;
    const char* scenes[] = {"s1", "s2", "s3"};
    for (size_t i = 0; i < 3; ++i) {
      CorrelationPoint p;
      p.scene = scenes[i];
      p.resolution = "64x64";
      p.gpu_median_us = 100;
      p.oovr_median_us = 100 * ratios[i];
      c.points.push_back(p);
    }
    c.r = 0.5;
    c.spread = *std::max_element(ratios.begin(), ratios.end()) / *std::min_element(ratios.begin(), ratios.end());
    return c;
  };
  const std::vector<LeftOut> l = leave_one_scene_out({"a", "b"}, {run({1, 1, 4}), run({1, 2, 2})});
  ASSERT_EQ(l.size(), 3u);
  // s1 out: the others are 1, 4 at a (sd of logs ln 2) and 2, 2 at b (0):
  // b; s1's ratio 1 against their 2: 0.5.
  EXPECT_EQ(l[0].scene, "s1");
  EXPECT_EQ(l[0].value, "b");
  EXPECT_DOUBLE_EQ(l[0].held_out, 0.5);
  EXPECT_DOUBLE_EQ(l[0].spread, 2.0);
  // s2 out: others 1, 4 at a, 1, 2 at b (sd ln 2 / 2): b; 2 against sqrt 2.
  EXPECT_EQ(l[1].value, "b");
  EXPECT_NEAR(l[1].held_out, std::sqrt(2.0), 1e-12);
  // s3 out: others 1, 1 at a (sd 0): a; 4 against 1.
  EXPECT_EQ(l[2].value, "a");
  EXPECT_DOUBLE_EQ(l[2].held_out, 4.0);
  EXPECT_DOUBLE_EQ(l[2].spread, 4.0);
  EXPECT_THROW((void)leave_one_scene_out({"a"}, {}), Error);
}

TEST(Hardware, BadDataIsOneClearError) {
  const std::string head = kWorkload + kHeader;
  const auto message = [](const std::string& text) {
    try {
      (void)HardwareData::parse(text, "bad.csv");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("").find("no header"), std::string::npos);
  EXPECT_NE(message(head).find("no frames"), std::string::npos);
  EXPECT_NE(message(kWorkload + "scene,frame\nx,1\n").find("no column 'resolution'"), std::string::npos);
  // A column named twice (found by fuzz_hardware: rows then had as many
  // fields as distinct names, and columns pointed past them).
  EXPECT_EQ(message(kWorkload + "scene,resolution,frame,full_us,geom_us,left_us,draws,triangles,draws\n"),
            "hardware data 'bad.csv' line 5: the header names the column 'draws' twice");
  EXPECT_NE(message(head + "courtyard,640x480,0,fast,1,1,61,5\n").find("line 6: 'full_us' is not a number"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640x480,0,1,1,1,61\n").find("line 6: has 7 fields"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640x480,0,-3,1,1,61,5\n").find("'full_us' is not a positive"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640x480,0,3,-1,1,61,5\n").find("negative"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640by480,0,1,1,1,61,5\n").find("640by480"), std::string::npos);
  EXPECT_THROW((void)HardwareData::read("/no/such/file.csv"), Error);
}

TEST(Hardware, CorrelationNeedsTwoPointsAndOneFrameSchemes) {
  HardwareData d = HardwareData::parse(kWorkload + kHeader + "courtyard,64x64,0,10,1,5,61,23288\n", "one.csv");
  CorrelationOptions o;
  EXPECT_THROW((void)correlate(d, o), Error);
  o.scheme = "afr";
  EXPECT_THROW((void)correlate(d, o), Error);
}

}  // namespace
}  // namespace oovr
