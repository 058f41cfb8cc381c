// The timing engine on cases with exact answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "oovr/core/error.h"
#include "oovr/core/rng.h"
#include "oovr/timing/engine.h"

namespace oovr {
namespace {

constexpr double kLink = 64e9;  // bytes per second

TEST(Timing, OneUnitAloneOnALinkTakesBytesOverBandwidthPlusLatency) {
  TimingEngine e;
  const int link = e.add_resource("link", kLink);
  e.add_unit({-1, {{link, 64e6}}, 32e-9, {}});
  const auto r = e.run();
  EXPECT_DOUBLE_EQ(r.units[0].work_done, 1e-3);
  EXPECT_DOUBLE_EQ(r.units[0].finish, 1e-3 + 32e-9);
  EXPECT_DOUBLE_EQ(r.resource_used[size_t(link)], 64e6);
}

// The engine registers each resource's use and capacity and each queue's
// busy time as statistics at their names (core/stats.h).
TEST(Timing, ReportsEachResourcesUseAndCapacityAndEachQueuesBusyTime) {
  TimingEngine e;
  const int link = e.add_resource("link[0->1]", kLink, "B");
  const int shader = e.add_resource("gpm[0].shader", 1e9);
  const int q = e.add_queue("gpm[0]");
  e.add_unit({q, {{link, 64e6}}, 1e-3, {}});  // 1 ms of work, 1 ms of latency
  e.add_unit({q, {{shader, 5e5}}, 0, {}});    // then 0.5 ms
  const auto r = e.run();
  Stats s;
  e.report(r, s);
  EXPECT_DOUBLE_EQ(s.at("link[0->1]", "used"), 64e6);
  EXPECT_EQ(s.find("link[0->1]", "used")->unit, "B");
  EXPECT_EQ(s.at("link[0->1]", "capacity"), kLink);
  EXPECT_EQ(s.find("link[0->1]", "capacity")->unit, "B/s");
  EXPECT_DOUBLE_EQ(s.at("gpm[0].shader", "used"), 5e5);
  EXPECT_EQ(s.find("gpm[0].shader", "capacity")->unit, "1/s");
  EXPECT_DOUBLE_EQ(s.at("gpm[0]", "queue_busy"), 2.5e-3);
  EXPECT_EQ(s.size(), 5u);
}

TEST(Timing, TwoUnitsSharingALinkTakeTwiceAsLong) {
  TimingEngine e;
  const int link = e.add_resource("link", kLink);
  e.add_unit({-1, {{link, 64e6}}, 0, {}});
  e.add_unit({-1, {{link, 64e6}}, 0, {}});
  const auto r = e.run();
  EXPECT_DOUBLE_EQ(r.units[0].finish, 2e-3);
  EXPECT_DOUBLE_EQ(r.units[1].finish, 2e-3);
}

TEST(Timing, AShortUnitReleasesItsShareWhenItEnds) {
  // 64 MB and 32 MB on one link: both run at half speed until the small
  // one ends at 1 ms (32 MB each moved); the big one then has 32 MB left
  // at full speed: 0.5 ms more.
  TimingEngine e;
  const int link = e.add_resource("link", kLink);
  e.add_unit({-1, {{link, 64e6}}, 0, {}});
  e.add_unit({-1, {{link, 32e6}}, 0, {}});
  const auto r = e.run();
  EXPECT_NEAR(r.units[1].finish, 1e-3, 1e-15);
  EXPECT_NEAR(r.units[0].finish, 1.5e-3, 1e-15);
}

TEST(Timing, TheBottleneckDecidesAndMovesWhenAResourceIsScaled) {
  for (double shader_rate : {1e9, 4e9}) {
    TimingEngine e;
    const int shader = e.add_resource("shader", shader_rate);
    const int dram = e.add_resource("dram", 1e12);
    e.add_unit({-1, {{shader, 2e6}, {dram, 1e9}}, 0, {}});
    const auto r = e.run();
    // shader: 2 ms at 1e9/s, 0.5 ms at 4e9/s; DRAM: 1 ms.
    EXPECT_DOUBLE_EQ(r.units[0].finish, std::max(2e6 / shader_rate, 1e-3)) << shader_rate;
  }
}

TEST(Timing, QueuesRunTheirUnitsInOrderAndDependenciesWait) {
  TimingEngine e;
  const int a = e.add_resource("a", 1.0), b = e.add_resource("b", 1.0);
  const int q0 = e.add_queue("gpm0"), q1 = e.add_queue("gpm1");
  const int u0 = e.add_unit({q0, {{a, 2}}, 0, {}});    // 0..2
  const int u1 = e.add_unit({q0, {{a, 1}}, 0.5, {}});  // 2..3 work, 3.5 with latency
  const int u2 = e.add_unit({q1, {{b, 1}}, 0, {u1}});  // waits for u1: 3.5..4.5
  const auto r = e.run();
  EXPECT_DOUBLE_EQ(r.units[size_t(u0)].finish, 2);
  EXPECT_DOUBLE_EQ(r.units[size_t(u1)].start, 2);
  EXPECT_DOUBLE_EQ(r.units[size_t(u1)].work_done, 3);
  EXPECT_DOUBLE_EQ(r.units[size_t(u1)].finish, 3.5);
  EXPECT_DOUBLE_EQ(r.units[size_t(u2)].start, 3.5);
  EXPECT_DOUBLE_EQ(r.units[size_t(u2)].finish, 4.5);
  EXPECT_DOUBLE_EQ(r.queue_busy[size_t(q0)], 3.5);
  EXPECT_DOUBLE_EQ(r.queue_busy[size_t(q1)], 1);
  EXPECT_DOUBLE_EQ(r.makespan, 4.5);
}

TEST(Timing, UnitsWithoutDemandsTakeOnlyTheirLatency) {
  TimingEngine e;
  e.add_unit({-1, {}, 0.25, {}});
  e.add_unit({-1, {}, 0, {0}});
  const auto r = e.run();
  EXPECT_DOUBLE_EQ(r.units[0].finish, 0.25);
  EXPECT_DOUBLE_EQ(r.units[1].finish, 0.25);
}

// A runtime scheduler adds work as units end, and reads progress: unit A
// (1 s on the shader) ends at 1 s while C (2 s alone on another resource)
// is half done; the hook then queues B behind A on the same queue and a
// unit D that depends on C.
TEST(Timing, UnitsAddedWhileRunningJoinAtTheCurrentTime) {
  TimingEngine e;
  const int shader = e.add_resource("shader", 1);
  const int rop = e.add_resource("rop", 1);
  const int q = e.add_queue("gpm");
  const int a = e.add_unit({q, {{shader, 1}}, 0, {}});
  const int c = e.add_unit({-1, {{rop, 2}}, 0, {}});
  int b = -1, d = -1;
  double c_left_at_a = -1;
  const auto r = e.run([&](int unit) {
    if (unit == a) {
      EXPECT_DOUBLE_EQ(e.now(), 1.0);
      EXPECT_TRUE(e.finished(a));
      EXPECT_TRUE(e.started(c));
      c_left_at_a = e.work_left(c);
      b = e.add_unit({q, {{shader, 1}}, 0, {a}});  // a is done: no wait
      d = e.add_unit({-1, {{shader, 1}}, 0, {c}});
    }
  });
  EXPECT_DOUBLE_EQ(c_left_at_a, 0.5);
  ASSERT_EQ(r.units.size(), 4u);
  EXPECT_DOUBLE_EQ(r.units[size_t(b)].start, 1.0);
  EXPECT_DOUBLE_EQ(r.units[size_t(b)].finish, 2.0);
  // D waits for C (2 s), then has the shader to itself.
  EXPECT_DOUBLE_EQ(r.units[size_t(d)].start, 2.0);
  EXPECT_DOUBLE_EQ(r.units[size_t(d)].finish, 3.0);
  EXPECT_DOUBLE_EQ(r.makespan, 3.0);
  EXPECT_THROW(e.run(), Error) << "an engine runs once";
}

TEST(Timing, BadUnitsAreRefused) {
  TimingEngine e;
  EXPECT_THROW(e.add_resource("x", 0), Error);
  const int r = e.add_resource("r", 1);
  EXPECT_THROW(e.add_unit({5, {}, 0, {}}), Error);
  EXPECT_THROW(e.add_unit({-1, {{r + 1, 1.0}}, 0, {}}), Error);
  EXPECT_THROW(e.add_unit({-1, {{r, -1.0}}, 0, {}}), Error);
  EXPECT_THROW(e.add_unit({-1, {}, 0, {0}}), Error) << "depends on itself";
}

TEST(Timing, ManyUnitsDeterministic) {
  // Four queues of 500 units with shared and private resources: the same
  // answer twice.
  auto build = [] {
    TimingEngine e;
    const int shared = e.add_resource("link", 3.0);
    std::vector<int> own;
    for (int q = 0; q < 4; ++q) {
      e.add_queue("q");
      own.push_back(e.add_resource("own", 1.0 + q));
    }
    for (int k = 0; k < 2000; ++k)
      e.add_unit({k % 4, {{own[size_t(k % 4)], 1.0 + (k * 37 % 11)}, {shared, double(k * 13 % 7)}}, (k % 3) * 0.01, {}});
    return e.run();
  };
  const auto a = build(), b = build();
  EXPECT_EQ(a.makespan, b.makespan);
  for (size_t i = 0; i < a.units.size(); ++i) EXPECT_EQ(a.units[i].finish, b.units[i].finish);
  EXPECT_GT(a.makespan, 0);
}

}  // namespace
}  // namespace oovr

// --- Work-conserving (max-min fair) sharing: units of unequal demand ---

namespace oovr {
namespace {

TEST(Sharing, AUnitLimitedElsewhereLeavesTheRestOfALinkToTheOther) {
  // A is bound by its own shader to 1 ms and needs 30% of the link at that
  // pace; B wants the whole link. Fair: A runs at full speed and B gets the
  // other 70% (44.8 GB/s) until A ends at 1 ms, then all of it: 44.8 MB +
  // 19.2 MB / 64 GB/s = 1.3 ms, the link busy all along. Split equally, B
  // gets 32 GB/s while A uses 19.2, and ends at 1.5 ms.
  for (Sharing s : {Sharing::fair, Sharing::equal}) {
    TimingEngine e;
    e.set_sharing(s);
    const int link = e.add_resource("link", kLink);
    const int shader = e.add_resource("shader", 1e9);
    e.add_unit({-1, {{shader, 1e6}, {link, 19.2e6}}, 0, {}});
    e.add_unit({-1, {{link, 64e6}}, 0, {}});
    const auto r = e.run();
    EXPECT_NEAR(r.units[0].finish, 1e-3, 1e-15);
    EXPECT_NEAR(r.units[1].finish, s == Sharing::fair ? 1.3e-3 : 1.5e-3, 1e-15);
    EXPECT_EQ(e.unconverged(), 0u);
  }
}

TEST(Sharing, ThreeUnitsOfUnequalDemandShareALinkByWaterFilling) {
  // Link of 1 unit/s. At full speed A would use 0.2 of it, B 0.5, C all.
  // Water level 0.4: A keeps 0.2, B and C get 0.4 each (B at 0.8 speed).
  // A ends at 1 s; B then gets its 0.5 (C 0.5) and ends at 1.2 s with
  // 0.2 of work left at full speed; C has 0.5 left at 1.2 s, alone: 1.7 s,
  // when the link has carried all 1.7 units, never idle.
  TimingEngine e;
  const int link = e.add_resource("link", 1.0);
  const int pa = e.add_resource("a", 1.0), pb = e.add_resource("b", 1.0);
  e.add_unit({-1, {{pa, 1.0}, {link, 0.2}}, 0, {}});
  e.add_unit({-1, {{pb, 1.0}, {link, 0.5}}, 0, {}});
  e.add_unit({-1, {{link, 1.0}}, 0, {}});
  const auto r = e.run();
  EXPECT_NEAR(r.units[0].finish, 1.0, 1e-12);
  EXPECT_NEAR(r.units[1].finish, 1.2, 1e-12);
  EXPECT_NEAR(r.units[2].finish, 1.7, 1e-12);
  EXPECT_NEAR(r.resource_used[size_t(link)], 1.7, 1e-12);
}

TEST(Sharing, AUnitBoundOnOneResourceLeavesItsShareOfAnotherToItsNeighbour) {
  // A uses X and Y; B uses X; C and D use Y (all demands 1, capacities 1).
  // Y is split three ways, so A runs at 1/3 and B takes the other 2/3 of X
  // (equal sharing would hold B at 1/2). B ends at 1.5; A, C and D have
  // 0.5 left each, at 1/3: 3.0.
  for (Sharing s : {Sharing::fair, Sharing::equal}) {
    TimingEngine e;
    e.set_sharing(s);
    const int x = e.add_resource("x", 1.0), y = e.add_resource("y", 1.0);
    e.add_unit({-1, {{x, 1.0}, {y, 1.0}}, 0, {}});
    e.add_unit({-1, {{x, 1.0}}, 0, {}});
    e.add_unit({-1, {{y, 1.0}}, 0, {}});
    e.add_unit({-1, {{y, 1.0}}, 0, {}});
    const auto r = e.run();
    EXPECT_NEAR(r.units[1].finish, s == Sharing::fair ? 1.5 : 2.0, 1e-12);
    if (s == Sharing::fair) {
      for (int u : {0, 2, 3}) EXPECT_NEAR(r.units[size_t(u)].finish, 3.0, 1e-12) << u;
    }
  }
}

TEST(Sharing, RandomUnitsAlwaysFitAndEachHasAFullBottleneckWhereNoOneGetsMore) {
  // The defining properties of the fair rates, on random machines: no
  // resource is asked for more than it has; every unit has a bottleneck, a
  // full resource on which no other user gets more than it (so no unit could
  // go faster without taking from one that gets no more).
  Rng rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const int resources = 1 + int(rng.uniform() * 6), units = 1 + int(rng.uniform() * 8);
    std::vector<double> capacity;
    for (int r = 0; r < resources; ++r) capacity.push_back(0.5 + rng.uniform() * 4);
    std::vector<Demand> demand(static_cast<size_t>(units));
    for (auto& d : demand) {
      for (int r = 0; r < resources; ++r)
        if (rng.uniform() < 0.5) d.push_back({r, 0.01 + rng.uniform() * 3});
      if (d.empty()) d.push_back({int(rng.uniform() * resources), 1.0});
    }
    std::vector<const Demand*> ptrs;
    for (const auto& d : demand) ptrs.push_back(&d);
    ResourceSharing sharing(capacity);
    const std::vector<double> rate = sharing.rates(ptrs, Sharing::fair);
    ASSERT_EQ(sharing.unconverged(), 0u) << trial;
    std::vector<double> used(size_t(resources), 0), most(size_t(resources), 0);
    for (int u = 0; u < units; ++u)
      for (const auto& [r, a] : demand[size_t(u)]) {
        used[size_t(r)] += a * rate[size_t(u)];
        most[size_t(r)] = std::max(most[size_t(r)], a * rate[size_t(u)]);
      }
    for (int r = 0; r < resources; ++r) ASSERT_LE(used[size_t(r)], capacity[size_t(r)] * (1 + 1e-9)) << trial;
    for (int u = 0; u < units; ++u) {
      bool bottleneck = false;
      for (const auto& [r, a] : demand[size_t(u)])
        bottleneck = bottleneck ||
                     (used[size_t(r)] >= capacity[size_t(r)] * (1 - 1e-9) && a * rate[size_t(u)] >= most[size_t(r)] * (1 - 1e-9));
      ASSERT_TRUE(bottleneck) << "trial " << trial << " unit " << u;
    }
  }
}

TEST(Sharing, AProblemMetAgainTakesTheLevelsItsIterationWouldGiveToTheBit) {
  // One object meets problems again (and keeps their levels); a fresh
  // object per call iterates each anew. Each round meets a mix of units,
  // then the mixes a key could confuse with it: one unit swapped for its
  // twin, the same on the shared resources (0 to 3) but bound lower by one
  // of its own (4 and up); the same amounts as one unit or as two; and the
  // first mix again.
  const int shared = 4, own = 6;
  std::vector<double> capacity;
  for (int r = 0; r < shared + own; ++r) capacity.push_back(1.0 + 0.37 * r);
  Rng rng(31);
  std::vector<Demand> units, twins;
  for (int u = 0; u < own; ++u) {
    Demand d;
    for (int r = 0; r < shared; ++r)
      if (rng.uniform() < 0.6) d.push_back({r, 0.5 + rng.uniform() * 2});
    if (d.empty()) d.push_back({int(rng.uniform() * shared), 1.0});
    d.push_back({shared + u, 0.5 + rng.uniform()});
    units.push_back(d);
    d.back().second *= 8;
    twins.push_back(d);
  }
  const Demand both{{0, 0.8}, {1, 0.3}}, first{{0, 0.8}}, second{{1, 0.3}};
  ResourceSharing kept(capacity);
  const auto same = [&](const std::vector<const Demand*>& running, int round) {
    for (Sharing s : {Sharing::fair, Sharing::equal}) {
      const std::vector<double> reused = kept.rates(running, s);
      ResourceSharing fresh(capacity);
      const std::vector<double>& iterated = fresh.rates(running, s);
      ASSERT_EQ(reused.size(), iterated.size());
      for (size_t k = 0; k < reused.size(); ++k)
        ASSERT_EQ(std::bit_cast<uint64_t>(reused[k]), std::bit_cast<uint64_t>(iterated[k])) << "round " << round << " unit " << k;
    }
  };
  for (int round = 0; round < 1500; ++round) {
    std::vector<const Demand*> mix;
    for (const Demand& d : units)
      if (rng.uniform() < 0.5) mix.push_back(&d);
    if (mix.empty()) mix.push_back(&units[0]);
    same(mix, round);
    std::vector<const Demand*> swapped = mix;
    const size_t j = size_t(rng.uniform() * double(mix.size()));
    swapped[j] = &twins[size_t(mix[j] - units.data())];
    same(swapped, round);
    std::vector<const Demand*> joined = mix, split = mix;
    joined.push_back(&both);
    split.push_back(&first);
    split.push_back(&second);
    same(joined, round);
    same(split, round);
    same(mix, round);
  }
  // Met again often enough to mean something, among a few hundred kinds.
  EXPECT_GT(kept.problems().reused(), 1500u);
  EXPECT_GT(kept.problems().solved(), 200u);
  // More problems than are kept: the table empties and fills again, and
  // answers as before.
  const uint64_t solved = kept.problems().solved();
  Demand changing = units[0];
  const std::vector<const Demand*> mix{&units[1], &units[2], &changing};
  for (size_t n = 0; n <= SolvedSharing::kKept + 100; ++n) {
    changing.front().second = 0.5 + double(n) * 1e-4;
    same(mix, -1);
    if (n % 997 == 0) same({&units[1], &units[2], &units[0]}, -2);
  }
  EXPECT_GT(kept.problems().solved(), solved + SolvedSharing::kKept);
}

// The fair rates as the damped iteration gives them, written out plainly:
// every step from the levels it is given, each user's other resources'
// limit found by looking at them all. ResourceSharing must give these bits
// whichever steps it leaves out.
std::vector<double> iterated_rates(const std::vector<double>& capacity, const std::vector<Demand>& demands) {
  const double inf = std::numeric_limits<double>::infinity();
  const size_t m = demands.size(), n = capacity.size();
  std::vector<std::vector<std::pair<size_t, double>>> users(n);
  for (size_t k = 0; k < m; ++k)
    for (const auto& [r, a] : demands[k])
      if (a > 0) users[size_t(r)].push_back({k, a});
  std::vector<double> own(m, inf);
  std::vector<size_t> shared;
  for (size_t r = 0; r < n; ++r) {
    if (users[r].size() > 1) shared.push_back(r);
    if (users[r].size() == 1) own[users[r][0].first] = std::min(own[users[r][0].first], capacity[r] / users[r][0].second);
  }
  std::vector<double> level = capacity, next(n);
  bool converged = shared.empty();
  for (int i = 0; i < 1000 && !converged; ++i) {
    for (size_t r : shared) {
      std::vector<double> wants;
      for (const auto& [k, a] : users[r]) {
        double other = inf;
        for (size_t q : shared)
          for (const auto& [j, b] : users[q])
            if (q != r && j == k) other = std::min(other, level[q] / b);
        wants.push_back(a * std::min(other, own[k]));
      }
      std::sort(wants.begin(), wants.end());
      double left = capacity[r];
      next[r] = capacity[r];
      for (size_t w = 0; w < wants.size(); ++w) {
        const double share = left / double(wants.size() - w);
        if (wants[w] > share) {
          next[r] = share;
          break;
        }
        left -= wants[w];
      }
    }
    converged = true;
    for (size_t r : shared)
      if (std::abs(next[r] - level[r]) > 1e-13 * capacity[r]) converged = false;
    for (size_t r : shared) level[r] = converged ? next[r] : 0.5 * (level[r] + next[r]);
  }
  std::vector<double> rate(m, inf);
  for (size_t k = 0; k < m; ++k) rate[k] = own[k];
  for (size_t r : shared)
    for (const auto& [k, a] : users[r]) rate[k] = std::min(rate[k], level[r] / a);
  for (size_t r : shared) {
    double used = 0;
    for (const auto& [k, a] : users[r]) used += a * rate[k];
    if (used > capacity[r])
      for (const auto& [k, a] : users[r]) rate[k] *= capacity[r] / used;
  }
  return rate;
}

TEST(Sharing, LevelsKnownFromTheFirstStepAreTheIterationsToTheBit) {
  // Machines like a frame's: links and a DRAM to spare, units bound by
  // their own shaders or not, amounts often equal (ties in the water line);
  // and machines where every unit uses every link.
  // Some problems settle at the first step on every resource, others on
  // some (ResourceSharing then leaves those resources' later steps out);
  // every rate is the plain iteration's.
  Rng rng(53);
  const double amounts[] = {1.0, 2.0, 0.5, 3.0};
  uint64_t settled = 0, partly = 0, problems = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const int links = 1 + int(rng.uniform() * 5), units = 2 + int(rng.uniform() * 7);
    std::vector<double> capacity;
    for (int r = 0; r < links; ++r) capacity.push_back(rng.uniform() < 0.3 ? 16.0 : 1.0 + double(int(rng.uniform() * 4)));
    std::vector<Demand> demand(static_cast<size_t>(units));
    // Every third machine: every unit on every link, nothing of its own.
    const bool dense = trial % 3 == 0;
    for (auto& d : demand) {
      for (int r = 0; r < links; ++r)
        if (dense || rng.uniform() < 0.45)
          d.push_back({r, rng.uniform() < 0.5 ? amounts[int(rng.uniform() * 4)] : 0.05 + rng.uniform() * 3});
      if (d.empty()) d.push_back({int(rng.uniform() * links), 1.0});
      if (!dense && rng.uniform() < 0.6) {
        capacity.push_back(rng.uniform() < 0.5 ? 1.0 : 0.2 + rng.uniform() * 3);
        d.push_back({int(capacity.size()) - 1, 1.0});
      }
    }
    std::vector<const Demand*> ptrs;
    for (const auto& d : demand) ptrs.push_back(&d);
    ResourceSharing sharing(capacity);
    const std::vector<double> rate = sharing.rates(ptrs, Sharing::fair);
    const std::vector<double> expected = iterated_rates(capacity, demand);
    ASSERT_EQ(rate.size(), expected.size());
    for (size_t k = 0; k < rate.size(); ++k)
      ASSERT_EQ(std::bit_cast<uint64_t>(rate[k]), std::bit_cast<uint64_t>(expected[k]))
          << "trial " << trial << " unit " << k << ": " << rate[k] << " against " << expected[k];
    settled += sharing.settled();
    partly += sharing.partly_settled();
    problems += sharing.problems().solved();
  }
  // Both ways are taken often: every resource's steps left out, or some
  // (with the others stepped, reading the levels of those left out).
  EXPECT_GT(settled, problems / 5) << settled << " of " << problems;
  EXPECT_GT(partly, problems / 5) << partly << " of " << problems;
}

}  // namespace
}  // namespace oovr
