// The statistics facility (core/stats.h): registration, snapshots that
// subtract, and a window's merge by each statistic's rule.
#include <gtest/gtest.h>

#include <cmath>

#include "oovr/core/error.h"
#include "oovr/core/stats.h"

namespace oovr {
namespace {

TEST(Stats, AStatisticIsRegisteredOnceAtItsLocation) {
  Stats s;
  s.count("gpm[0].dram", "bytes", 4096, "B");
  s.add("gpm[0]", "queue_busy", 1.5e-3, "s");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.at("gpm[0].dram", "bytes"), 4096);
  EXPECT_EQ(s.find("gpm[0].dram", "bytes")->unit, "B");
  EXPECT_TRUE(s.find("gpm[0].dram", "bytes")->whole);
  EXPECT_EQ(s.find("gpm[0].dram", "bytes")->merge, Merge::sum);
  EXPECT_EQ(s.find("gpm[0]", "queue_busy")->merge, Merge::mean);
  EXPECT_EQ(s.find("gpm[1].dram", "bytes"), nullptr);
  EXPECT_THROW(s.at("gpm[1].dram", "bytes"), Error);
  // One owner each: the same location and name again is refused, another
  // name at the location is not.
  EXPECT_THROW(s.add("gpm[0].dram", "bytes", 1), Error);
  EXPECT_THROW(s.count("gpm[0].dram", "bytes", 1), Error);
  s.add("gpm[0].dram", "capacity", 1e12, "B/s", Merge::max);
  Stats other;
  other.add("gpm[0]", "queue_busy", 1);
  EXPECT_THROW(s.append(other), Error);
  EXPECT_THROW(s.add("x", "nan", std::nan("")), Error);
  EXPECT_THROW(s.count("x", "huge", uint64_t(1) << 53), Error);
}

TEST(Stats, AFramesStatisticsAreTheDifferenceOfTwoSnapshots) {
  const auto snapshot = [](uint64_t bytes, double peak) {
    Stats s;
    s.count("link[0->1]", "bytes", bytes, "B");
    s.add("memory", "peak", peak, "B", Merge::max);
    return s;
  };
  const Stats frame = snapshot(1500, 7).since(snapshot(1000, 5));
  EXPECT_EQ(frame.at("link[0->1]", "bytes"), 500);  // counts subtract
  EXPECT_EQ(frame.at("memory", "peak"), 7);         // the others are as now
  Stats other;
  other.count("link[1->0]", "bytes", 1);
  other.add("memory", "peak", 1);
  EXPECT_THROW(frame.since(other), Error);
  EXPECT_THROW(frame.since(Stats{}), Error);
}

TEST(Stats, AWindowMergesEachStatisticByItsRule) {
  Stats a, b, c;
  a.count("memory", "accesses", 3);
  a.add("gpm[0].shader", "used", 1.0, "", Merge::sum);
  a.add("gpm[0]", "queue_busy", 2.0, "s");
  a.add("gpm[0].shader", "capacity", 5, "1/s", Merge::max);
  b.count("memory", "accesses", 4);
  b.add("gpm[0].shader", "used", 2.0, "", Merge::sum);
  b.add("gpm[0]", "queue_busy", 4.0, "s");
  b.add("gpm[0].shader", "capacity", 9, "1/s", Merge::max);
  b.add("oo-vr", "batches", 10);  // reported by one run only
  c = b;
  const Stats w = Stats::window({&a, &b}, 2);
  ASSERT_EQ(w.size(), 5u);
  EXPECT_EQ(w.at("memory", "accesses"), 4);       // 7 over 2 frames, to nearest as whole counts divide
  EXPECT_EQ(w.at("gpm[0].shader", "used"), 1.5);  // not whole: not rounded
  EXPECT_EQ(w.at("gpm[0]", "queue_busy"), 3.0);   // the mean over the runs
  EXPECT_EQ(w.at("gpm[0].shader", "capacity"), 9);
  EXPECT_EQ(w.at("oo-vr", "batches"), 10);  // the mean over the runs that report it
  // In order of first appearance.
  EXPECT_EQ(w.all()[0].name, "accesses");
  EXPECT_EQ(w.all()[4].location, "oo-vr");
  // Frames in flight: two runs of two frames each are four frames.
  EXPECT_EQ(Stats::window({&a, &b}, 4).at("memory", "accesses"), 2);  // 7 / 4 = 1.75
  EXPECT_EQ(Stats::window({&a}, 1).at("memory", "accesses"), 3);
  // The runs of a window must agree on each statistic's rule.
  Stats d;
  d.add("memory", "accesses", 1);
  EXPECT_THROW(Stats::window({&a, &d}, 2), Error);
}

}  // namespace
}  // namespace oovr
