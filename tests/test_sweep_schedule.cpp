// The sweep engine's order of work (sweep_schedule.h): one pool over all
// groups of points, the next group loading while the one before runs, and
// the prediction of a sweep's time on more workers.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "oovr/experiments/sweep_schedule.h"

namespace oovr {
namespace {

using Kind = SweepSchedule::Action::Kind;

void expect(const SweepSchedule::Action& a, Kind kind, size_t group = 0, size_t point = 0) {
  EXPECT_EQ(int(a.kind), int(kind));
  if (kind == Kind::load || kind == Kind::point) {
    EXPECT_EQ(a.group, group);
  }
  if (kind == Kind::point) {
    EXPECT_EQ(a.point, point);
  }
}

TEST(SweepSchedule, OneWorkerLoadsEachGroupWhenTheOneBeforeIsDone) {
  SweepSchedule s({2, 1}, 1, 1000);
  expect(s.next(), Kind::load, 0);
  expect(s.next(), Kind::wait);  // nothing to do while it loads
  s.loaded(0, true, 10);
  expect(s.next(), Kind::point, 0, 0);
  expect(s.next(), Kind::point, 0, 1);
  expect(s.next(), Kind::wait);  // no load ahead with one worker
  EXPECT_FALSE(s.point_done(0));
  EXPECT_TRUE(s.point_done(0));
  EXPECT_FALSE(s.held(0));
  expect(s.next(), Kind::load, 1);
  s.loaded(1, true, 10);
  expect(s.next(), Kind::point, 1, 0);
  expect(s.next(), Kind::wait);
  EXPECT_TRUE(s.point_done(1));
  expect(s.next(), Kind::stop);
}

TEST(SweepSchedule, MoreWorkersLoadOneGroupAheadWithinHalfTheBudget) {
  SweepSchedule s({2, 1, 1}, 3, 1000);
  expect(s.next(), Kind::load, 0);
  expect(s.next(), Kind::wait);  // not two loads before the first's size is known
  s.loaded(0, true, 250);
  expect(s.next(), Kind::load, 1);  // 250 held, 250 more expected: a load first, so that it overlaps group 0's points
  expect(s.next(), Kind::point, 0, 0);
  expect(s.next(), Kind::point, 0, 1);
  s.loaded(1, true, 10);
  expect(s.next(), Kind::point, 1, 0);
  expect(s.next(), Kind::wait);  // two groups held: no third
  EXPECT_FALSE(s.point_done(0));
  EXPECT_TRUE(s.point_done(0));
  EXPECT_TRUE(s.held(1));
  expect(s.next(), Kind::load, 2);
  // Traces beyond half the budget: no load ahead.
  SweepSchedule big({1, 1}, 2, 1000);
  expect(big.next(), Kind::load, 0);
  big.loaded(0, true, 251);
  expect(big.next(), Kind::point, 0, 0);
  expect(big.next(), Kind::wait);
  EXPECT_TRUE(big.point_done(0));
  expect(big.next(), Kind::load, 1);
}

TEST(SweepSchedule, ManyWorkersLoadSeveralGroupsAheadAtOnceWithinHalfTheBudget) {
  // 16 workers: 4 groups ahead of the earliest held.
  SweepSchedule s({1, 1, 1, 1, 1, 1, 1}, 16, 10000);
  expect(s.next(), Kind::load, 0);
  expect(s.next(), Kind::wait);  // no size to go by yet
  s.loaded(0, true, 100);
  for (size_t g = 1; g <= 4; ++g) expect(s.next(), Kind::load, g);  // loading together
  expect(s.next(), Kind::point, 0, 0);
  expect(s.next(), Kind::wait);  // five groups held
  s.loaded(2, true, 100);
  expect(s.next(), Kind::point, 2, 0);  // group 1 still loading: group 2's points go first
  EXPECT_TRUE(s.point_done(0));
  expect(s.next(), Kind::load, 5);
  // Half the budget: 200 bytes loaded, each load counted as 200 more.
  SweepSchedule m({1, 1, 1, 1}, 16, 1200);
  expect(m.next(), Kind::load, 0);
  m.loaded(0, true, 200);
  expect(m.next(), Kind::load, 1);  // 200 + 200
  expect(m.next(), Kind::load, 2);  // 200 + 200 + 200 = 600, half of 1200
  expect(m.next(), Kind::point, 0, 0);
  expect(m.next(), Kind::wait);
  m.loaded(1, true, 10);
  expect(m.next(), Kind::point, 1, 0);
  expect(m.next(), Kind::wait);  // 200 + 10 + 200 + 200 > 600
  EXPECT_TRUE(m.point_done(0));
  expect(m.next(), Kind::load, 3);  // 10 + 200 + 200
}

TEST(SweepSchedule, AFailedLoadRunsNoneOfItsPoints) {
  SweepSchedule s({3, 1}, 2, 1000);
  expect(s.next(), Kind::load, 0);
  s.loaded(0, false, 0);
  EXPECT_FALSE(s.held(0));
  expect(s.next(), Kind::load, 1);
  s.loaded(1, true, 1);
  expect(s.next(), Kind::point, 1, 0);
  EXPECT_TRUE(s.point_done(1));
  expect(s.next(), Kind::stop);
  EXPECT_THROW(s.loaded(1, true, 1), std::exception);   // loaded twice
  EXPECT_THROW((void)s.point_done(1), std::exception);  // more points than ran
}

TEST(SweepSchedule, PredictionsOfHandWorkedSchedules) {
  // One group, loading 1 s, points of 4 s, on 2 workers: 1 + 4 + 4.
  const std::vector<GroupDurations> one = {{1, {4, 4, 4}}};
  EXPECT_DOUBLE_EQ(predict_schedule(one, 2, true).wall_s, 9);
  EXPECT_DOUBLE_EQ(predict_schedule(one, 2, false).wall_s, 9);
  // Two groups, each loading 1 s, then points of 3 s and 1 s. With a barrier
  // per group: (1 + 3) twice. One pool: group 1 loads during group 0's long
  // point and its points follow at once: load 0 [0,1]; load 1 [1,2] and
  // point 0.0 [1,4]; point 0.1 [2,3]; point 1.0 [3,6]; point 1.1 [4,5].
  const std::vector<GroupDurations> two = {{1, {3, 1}}, {1, {3, 1}}};
  EXPECT_DOUBLE_EQ(predict_schedule(two, 2, true).wall_s, 8);
  const PredictedSchedule pool = predict_schedule(two, 2, false);
  EXPECT_DOUBLE_EQ(pool.wall_s, 6);
  EXPECT_DOUBLE_EQ(pool.busy_s, 10);
  EXPECT_DOUBLE_EQ(pool.efficiency(2), 10.0 / 12.0);
  // One worker: the durations summed, whatever the engine.
  for (bool barrier : {true, false}) EXPECT_DOUBLE_EQ(predict_schedule(two, 1, barrier).wall_s, 10);
  // Many workers: never shorter than the longest chain of a load and its
  // group's longest point, never longer than one worker.
  std::vector<GroupDurations> many;
  for (int g = 0; g < 20; ++g) many.push_back({0.5, std::vector<double>(size_t(5 + g % 7), 1.0 + g % 3)});
  const double total = predict_schedule(many, 1, false).wall_s;
  for (unsigned w : {2u, 4u, 16u, 64u}) {
    const double t = predict_schedule(many, w, false).wall_s;
    EXPECT_GE(t, 0.5 + 3.0);
    EXPECT_LE(t, total);
    EXPECT_LE(t, predict_schedule(many, w, true).wall_s) << w << " workers";
  }
  EXPECT_THROW((void)predict_schedule(two, 0, false), std::exception);
}

}  // namespace
}  // namespace oovr

namespace oovr {
namespace {

// Points ending at the given costs, one after the other.
std::vector<double> ends(const std::vector<double>& costs) {
  std::vector<double> t;
  double now = 0;
  for (double c : costs) t.push_back(now += c);
  return t;
}

TEST(SweepSchedule, TheTimeLeftFollowsTheRecentRateWhenPointsGrowCostly) {
  // 100 points: 50 of 1 s, then 50 of 3 s (the built-in scenes, then the
  // game levels). At 60 done (80 s), 40 are left: 120 s.
  std::vector<double> costs(50, 1.0);
  costs.insert(costs.end(), 50, 3.0);
  const std::vector<double> t = ends(std::vector<double>(costs.begin(), costs.begin() + 60));
  const double whole = 80.0 / 60 * 40;  // 53 s: the run's mean rate
  // The last 15 points (a quarter) took 80 - 45 = 35 s: 40 x 35 / 15.
  EXPECT_NEAR(estimate_seconds_left(t, 100, 80), 40 * 35.0 / 15, 1e-9);
  EXPECT_GT(estimate_seconds_left(t, 100, 80), 1.7 * whole);
  // Even costs: the recent rate is the whole run's.
  const std::vector<double> even = ends(std::vector<double>(40, 1.0));
  EXPECT_NEAR(estimate_seconds_left(even, 100, 40), 60, 1e-9);
  // Points growing cheaper: never below the whole run's rate.
  std::vector<double> cheaper(30, 3.0);
  cheaper.insert(cheaper.end(), 30, 1.0);
  EXPECT_NEAR(estimate_seconds_left(ends(cheaper), 100, 120), 120.0 / 60 * 40, 1e-9);
  // Nothing finished: unknown; everything: nothing left; few: the mean.
  EXPECT_TRUE(std::isnan(estimate_seconds_left({}, 10, 5)));
  EXPECT_EQ(estimate_seconds_left(even, 40, 40), 0);
  EXPECT_NEAR(estimate_seconds_left(ends({2, 2, 2}), 10, 6), 14, 1e-9);
}

}  // namespace
}  // namespace oovr
