// Hardware data and the correlation statistics (experiments/hardware.h).
#include <gtest/gtest.h>

#include <cmath>

#include "oovr/core/error.h"
#include "oovr/experiments/hardware.h"

namespace oovr {
namespace {

TEST(Hardware, PearsonOnKnownSeries) {
  EXPECT_DOUBLE_EQ(pearson({1, 2, 3}, {2, 4, 6}), 1.0);
  EXPECT_DOUBLE_EQ(pearson({1, 2, 3}, {6, 4, 2}), -1.0);
  // x = 1..4, y = 1, 3, 2, 4: co-deviation 4, deviations 5 and 5: r = 4/5.
  EXPECT_NEAR(pearson({1, 2, 3, 4}, {1, 3, 2, 4}), 0.8, 1e-12);
  EXPECT_EQ(pearson({1, 1, 1}, {1, 2, 3}), 0.0) << "a constant series correlates with nothing";
  EXPECT_EQ(pearson({1}, {1}), 0.0);
}

TEST(Hardware, ReadsTheCsvAndWritesItBack) {
  const std::string text =
      "renderer,Some GPU/PCIe\n"
      "scene,resolution,frame,full_us,geom_us,left_us,draws,triangles\n"
      "courtyard,640x480,0,115.5,47.7,60.1,61,23288\n"
      "courtyard,1280x1024,3,377.9,47.4,191.1,61,23288\n";
  const HardwareData d = HardwareData::parse(text, "t.csv");
  EXPECT_EQ(d.renderer, "Some GPU/PCIe");
  ASSERT_EQ(d.frames.size(), 2u);
  EXPECT_EQ(d.frames[1].resolution, "1280x1024");
  EXPECT_EQ(d.frames[1].frame, 3);
  EXPECT_DOUBLE_EQ(d.frames[0].full_us, 115.5);
  EXPECT_EQ(d.frames[0].draws, 61u);
  EXPECT_EQ(HardwareData::parse(d.csv(), "again").csv(), d.csv());
}

TEST(Hardware, BadDataIsOneClearError) {
  const std::string head = "scene,resolution,frame,full_us,geom_us,left_us,draws,triangles\n";
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
  EXPECT_NE(message("scene,frame\nx,1\n").find("no column 'resolution'"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640x480,0,fast,1,1,61,5\n").find("line 2: 'full_us' is not a number"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640x480,0,1,1,1,61\n").find("line 2: has 7 fields"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640x480,0,-3,1,1,61,5\n").find("'full_us' is not a positive"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640x480,0,3,-1,1,61,5\n").find("negative"), std::string::npos);
  EXPECT_NE(message(head + "courtyard,640by480,0,1,1,1,61,5\n").find("640by480"), std::string::npos);
  EXPECT_THROW((void)HardwareData::read("/no/such/file.csv"), Error);
}

TEST(Hardware, CorrelationNeedsTwoPointsAndOneFrameSchemes) {
  HardwareData d = HardwareData::parse(
      "scene,resolution,frame,full_us,geom_us,left_us,draws,triangles\ncourtyard,64x64,0,10,1,5,61,23288\n", "one.csv");
  CorrelationOptions o;
  EXPECT_THROW((void)correlate(d, o), Error);
  o.scheme = "afr";
  EXPECT_THROW((void)correlate(d, o), Error);
}

}  // namespace
}  // namespace oovr
