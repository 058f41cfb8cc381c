// The paper's claims as data (experiments/paper-claims.toml).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "oovr/experiments/claims.h"
#include "oovr/experiments/results_db.h"
#include "oovr/run/result_json.h"
#include "oovr/schemes/i_scheme.h"
#include "test_util.h"

namespace oovr {
namespace {

using test::message_of;

TEST(Claims, TheCarriedFileHoldsP1ToP18WithKnownSchemesAndKeys) {
  const auto& claims = paper_claims();
  ASSERT_EQ(claims.size(), 18u);
  std::set<std::string> ids;
  for (const Claim& c : claims) {
    ids.insert(c.id);
    for (const ClaimValue& v : c.values) {
      EXPECT_TRUE(Schemes::find(v.scheme)) << c.id << ": " << v.scheme;
      EXPECT_TRUE(Schemes::find(v.against)) << c.id << ": " << v.against;
    }
  }
  for (int i = 1; i <= 18; ++i) {
    std::string id = "P";
    id += std::to_string(i);  // not "P" + ...: gcc 12 warns falsely (-Wrestrict)
    EXPECT_TRUE(ids.count(id)) << id;
  }
  // Every setting resolves to the number the database stores.
  const auto j = resolved_claims_json(claims);
  EXPECT_EQ(j["claims"][0]["values"][0]["set"]["link.bandwidth"], 128e9);
  EXPECT_EQ(j["claims"][0]["values"][0]["against_set"]["link.bandwidth"], 1e12);
  EXPECT_EQ(j["defaults"]["link.bandwidth"], 64e9);
  EXPECT_EQ(j["defaults"]["memory.placement"], "first-touch");
  // The paper's numbers as ratios: P1 at 64 GB/s is -42%, P14 OO-VR at 8 GPMs 6.27x.
  EXPECT_DOUBLE_EQ(*claims[0].values[1].paper, 0.58);
  EXPECT_DOUBLE_EQ(*claims[13].values[2].paper, 6.27);
  EXPECT_FALSE(claims[7].values[0].paper);  // P8: figure only
  // P18: energy beside the traffic claims; the paper gives words, no number.
  EXPECT_EQ(claims[17].values[0].measure, "link_energy");
  EXPECT_EQ(claims[17].values[2].measure, "energy");
  EXPECT_FALSE(claims[17].values[0].paper);
  // The comparison document's tolerances are the claims file's.
  EXPECT_DOUBLE_EQ(*claims[1].values[0].tolerance, 0.25);  // P2
  EXPECT_FALSE(claims[3].values[0].tolerance);             // P4: direction only
  // Each claim says what oovr must show to agree with it.
  for (const Claim& c : claims) EXPECT_FALSE(c.checks.empty()) << c.id;
  EXPECT_EQ(claims[0].checks[0].part, "direction");
  EXPECT_EQ(claims[0].checks[0].when[0].rising.size(), 5u);
}

TEST(Claims, BadFilesAreRefused) {
  const auto error = [](const std::string& text) { return message_of([&] { (void)parse_claims(text, "c.toml"); }); };
  EXPECT_NE(error("x = 1\n").find("no [[claim]]"), std::string::npos);
  const std::string head = "[[claim]]\nid = 'P1'\nsection = '1'\nfigure = 'f'\nwhat = 'w'\nwords = 'x'\nshort = 's'\n";
  EXPECT_NE(error(head).find("has no [[claim.value]]"), std::string::npos);
  const std::string value = "[[claim.value]]\nlabel = 'l'\nscheme = 'baseline'\nform = 'times'\n";
  EXPECT_NE(error(head + value + "measure = 'speed'\n").find("measure 'speed'"), std::string::npos);
  EXPECT_NE(error(head + value + "measure = 'speedup'\npaper = -1\n").find("line"), std::string::npos);
  EXPECT_NE(error(head + value + "measure = 'speedup'\nset = 3\n").find("set is a table"), std::string::npos);
  EXPECT_EQ(error(head + value + "measure = 'speedup'\npaper = 1.5\n"), "<no error>");
  // A tolerance is a positive number, and needs the paper's number it is near.
  EXPECT_EQ(error(head + value + "measure = 'speedup'\npaper = 1.5\ntolerance = 0.2\n"), "<no error>");
  EXPECT_NE(error(head + value + "measure = 'speedup'\npaper = 1.5\ntolerance = 0\n").find("tolerance takes a positive number"),
            std::string::npos);
  EXPECT_NE(error(head + value + "measure = 'speedup'\ntolerance = 0.2\n").find("tolerance without the paper's number"),
            std::string::npos);
  // A setting no component takes is an error naming the claim.
  const auto bad = parse_claims(head + value + "measure = 'speedup'\nset = { 'link.bandwith' = '1TBps' }\n", "c.toml");
  EXPECT_NE(message_of([&] { (void)resolved_claims_json(bad); }).find("P1 (l)"), std::string::npos);
}

// The checks' vocabulary, read: each mistake named.
TEST(Claims, BadChecksAreRefused) {
  const auto error = [](const std::string& checks) {
    const std::string text =
        "[[claim]]\nid = 'P1'\nsection = '1'\nfigure = 'f'\nwhat = 'w'\nwords = 'x'\nshort = 's'\n"
        "[[claim.value]]\nlabel = 'a'\nscheme = 'baseline'\nform = 'times'\nmeasure = 'speedup'\npaper = 1.5\ntolerance = 0.2\n"
        "[[claim.value]]\nlabel = 'b'\nscheme = 'afr'\nform = 'times'\nmeasure = 'speedup'\n" +
        checks;
    return message_of([&] { (void)parse_claims(text, "c.toml"); });
  };
  const std::string check = "[[claim.check]]\nsays = 's'\n";
  EXPECT_EQ(error(check + "over = 'all'\nwhen = [ { value = 'a', above = 'b' } ]\n"), "<no error>");
  EXPECT_EQ(error(check + "over = 'mean'\nwhen = [ { value = 'b', below = 'a', gain = 0.5 }, { value = 'a', near = true } ]\n"),
            "<no error>");
  EXPECT_EQ(error(check + "over = 'most'\nwhen = [ { rising = ['a', 'b'] } ]\n"), "<no error>");
  EXPECT_NE(error(check + "over = 'some'\nwhen = [ { value = 'a', above = 1 } ]\n").find("over 'some' (all, most or mean)"),
            std::string::npos);
  EXPECT_NE(error("[[claim.check]]\nover = 'all'\nwhen = [ { value = 'a', above = 1 } ]\n").find("missing says"),
            std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\n").find("needs when = [ conditions ]"), std::string::npos);
  EXPECT_NE(
      error(check + "over = 'all'\nwhen = [ { value = 'c', above = 1 } ]\n").find("P1 has no value 'c' (its values: 'a', 'b')"),
      std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'a', above = 'c' } ]\n").find("has no value 'c'"), std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'a', beyond = 1 } ]\n").find("no key 'beyond'"), std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'a', above = 1, below = 2 } ]\n").find("compares one way"),
            std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'a' } ]\n").find("needs one of above"), std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'b', near = true } ]\n").find("near needs the value's tolerance"),
            std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'a', above = 1, gain = 2 } ]\n").find("gain compares with another"),
            std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'a', above = 'b', gain = -1 } ]\n").find("gain takes a positive"),
            std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { rising = ['a'] } ]\n").find("rising takes two or more"), std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ 1 ]\n").find("a condition is a table"), std::string::npos);
  EXPECT_NE(error(check + "over = 'all'\nwhen = [ { value = 'a', above = 1 } ]\ncolour = 'red'\n").find("no key 'colour'"),
            std::string::npos);
}

// The one judgement of the claims: each check on the values measured, over
// every scene, most of them, or the means.
TEST(Claims, ChecksAreJudgedOnTheMeasuredValues) {
  const std::string values =
      "[[claim]]\nid = 'T'\nsection = '1'\nfigure = 'f'\nwhat = 'w'\nwords = 'x'\nshort = 's'\n"
      "[[claim.value]]\nlabel = 'a'\nscheme = 'baseline'\nform = 'times'\nmeasure = 'speedup'\npaper = 1.5\ntolerance = 0.2\n"
      "[[claim.value]]\nlabel = 'b'\nscheme = 'afr'\nform = 'times'\nmeasure = 'speedup'\n"
      "[[claim.value]]\nlabel = 'c'\nscheme = 'object'\nform = 'times'\nmeasure = 'speedup'\n"
      "[[claim.value]]\nlabel = 'never'\nscheme = 'oo-vr'\nform = 'times'\nmeasure = 'speedup'\n";
  const auto check = [](const std::string& over, const std::string& when) {
    return "[[claim.check]]\nsays = 's'\nover = '" + over + "'\nwhen = [ " + when + " ]\n";
  };
  const auto claims = parse_claims(values + check("all", "{ value = 'a', above = 1 }") +                             // 0
                                       check("most", "{ value = 'a', above = 'b' }") +                               // 1
                                       check("mean", "{ value = 'a', near = true }") +                               // 2
                                       check("all", "{ rising = ['c', 'b', 'a'] }") +                                // 3
                                       check("mean", "{ value = 'b', below = 'a', gain = 0.5 }") +                   // 4
                                       check("all", "{ value = 'never', above = 1 }") +                              // 5
                                       check("mean", "{ value = 'c', at_most = 1 }") +                               // 6
                                       check("all", "{ value = 'a', above = 1 }, { value = 'b', above = 0.6 }") +    // 7
                                       check("most", "{ value = 'c', below = 'a' }, { value = 'a', above = 1.5 }"),  // 8
                                   "t.toml");
  const auto per = [](std::vector<std::pair<std::string, double>> xs, double mean) {
    ClaimMeasured m;
    for (const auto& [scene, x] : xs) m.per.emplace_back(scene, "160x128", x);
    m.mean = mean;
    return m;
  };
  std::vector<std::vector<ClaimMeasured>> measured = {{
      per({{"s1", 1.4}, {"s2", 1.6}, {"s3", 0.9}}, 1.4),
      per({{"s1", 1.1}, {"s2", 1.7}, {"s3", 0.5}}, 1.15),
      per({{"s1", 1.0}, {"s2", 1.0}}, 1.0 + 1e-12),  // not measured on s3; its mean 1 but for rounding
      per({}, std::nan("")),
  }};
  auto v = judge_claims(claims, measured)[0];
  ASSERT_EQ(v.size(), 9u);
  EXPECT_TRUE(v[0].measured);
  EXPECT_FALSE(v[0].holds);  // s3: 0.9
  EXPECT_EQ(v[0].met, 2);
  EXPECT_EQ(v[0].of, 3);
  EXPECT_TRUE(v[1].holds);  // s1 and s3 of three
  EXPECT_EQ(v[1].met, 2);
  EXPECT_TRUE(v[2].holds);  // 1.4 within 0.2 of 1.5
  EXPECT_EQ(v[2].of, 1);
  EXPECT_FALSE(v[3].holds);  // s2: b 1.7 above a 1.6; s3 has no c, so is not counted
  EXPECT_EQ(v[3].met, 1);
  EXPECT_EQ(v[3].of, 2);
  EXPECT_TRUE(v[4].holds);  // b's gain 0.15 below half a's 0.4
  EXPECT_FALSE(v[5].measured);
  EXPECT_FALSE(v[5].holds);
  EXPECT_TRUE(v[6].holds);   // at most 1 within rounding
  EXPECT_FALSE(v[7].holds);  // every condition on the same scene: s3 fails both
  EXPECT_EQ(v[7].met, 2);
  EXPECT_FALSE(v[8].holds);  // half the scenes is not most
  EXPECT_EQ(v[8].met, 1);
  EXPECT_EQ(v[8].of, 2);
  // Each verdict moves with what it judges.
  measured[0][0].mean = 1.75;
  measured[0][1].mean = 1.5;
  measured[0][2].mean = 1.01;
  measured[0][1].per[1] = {"s2", "160x128", 1.5};
  measured[0][0].per[2] = {"s3", "160x128", 1.2};
  v = judge_claims(claims, measured)[0];
  EXPECT_TRUE(v[0].holds);
  EXPECT_EQ(v[1].met, 3);
  EXPECT_FALSE(v[2].holds);  // 1.75 is 0.25 from 1.5
  EXPECT_TRUE(v[3].holds);
  EXPECT_FALSE(v[4].holds);  // b's gain 0.5 above half a's 0.75
  EXPECT_FALSE(v[6].holds);
}

// A done run of `scheme` on `scene` with `throughput` frames per second,
// on the paper's machine but for `set`, as a database holds it.
RunRecord stored_run(const std::string& scene, const std::string& scheme, double throughput, const std::string& set = "",
                     int position = 0) {
  Config c;
  if (!set.empty()) c.set(set);
  RunRecord r;
  r.sweep = "s";
  r.position = position;
  r.scene = scene;
  r.scheme = scheme;
  r.resolution = "160x128";
  r.status = "done";
  r.config = to_json(scheme_entries(scheme, MachineSpec::from_config(c).entries));
  r.metrics = {{"frame", "throughput", throughput, "frames/s"}, {"frame", "latency", 1 / throughput, "s"}};
  return r;
}

// The claims measured in stored runs (the one evaluation, which `oovr
// report` draws): each value's ratio per scene from the runs on the paper's
// machine with only its settings changed, against its `against` run of the
// same scene, and their geometric mean.
TEST(Claims, AValueIsMeasuredOnTheRunsOfItsSetupOnly) {
  const std::vector<RunRecord> runs = {
      stored_run("a", "baseline", 100),
      stored_run("a", "afr", 200),
      stored_run("a", "afr", 900, "link.bandwidth=32GBps"),  // another setup: not P2's
      stored_run("b", "baseline", 25, "", 1),
      stored_run("b", "afr", 50, "", 1),
      stored_run("c", "afr", 300),  // no baseline to be relative to
  };
  const std::vector<Claim>& claims = paper_claims();
  const auto measured = measure_claims(claims, runs);
  ASSERT_EQ(measured.size(), claims.size());
  ASSERT_EQ(claims[1].id, "P2");
  const ClaimMeasured& p2 = measured[1][0];  // AFR's throughput over the baseline's
  ASSERT_EQ(p2.per.size(), 2u);
  EXPECT_EQ(p2.per[0], std::make_tuple(std::string("a"), std::string("160x128"), 2.0));
  EXPECT_EQ(p2.per[1], std::make_tuple(std::string("b"), std::string("160x128"), 2.0));  // against b's baseline
  EXPECT_DOUBLE_EQ(p2.mean, 2.0);
  // P1 at 128 GB/s needs baseline runs at 128 GB/s and 1 TB/s: none here.
  EXPECT_TRUE(measured[0][0].per.empty());
  EXPECT_TRUE(std::isnan(measured[0][0].mean));
  // A key the run does not read (OO-VR's own, in a baseline run) is no
  // difference; one the value sets must be there.
  EXPECT_TRUE(on_paper_setup(runs[0], "baseline", nlohmann::ordered_json::object()));
  EXPECT_FALSE(on_paper_setup(runs[0], "baseline", {{"oo.batch_queue", 4}}));
  EXPECT_FALSE(on_paper_setup(runs[2], "afr", nlohmann::ordered_json::object()));
  EXPECT_TRUE(on_paper_setup(runs[2], "afr", {{"link.bandwidth", 32e9}}));
}

// P18 sets energy beside the traffic claims: each value's energy ratio to
// the baseline's on the same scene (the links' alone, or the memory
// system's), judged on the means.
TEST(Claims, EnergyIsMeasuredAgainstTheBaselinesEnergy) {
  std::vector<RunRecord> runs = {stored_run("a", "baseline", 100), stored_run("a", "oo-vr", 100), stored_run("a", "object", 100)};
  const auto energy = [](RunRecord& r, double total, double links) {
    r.metrics.push_back({"frame", "energy", total, "J"});
    r.metrics.push_back({"frame", "energy.links", links, "J"});
  };
  energy(runs[0], 4e-3, 1e-3);
  energy(runs[1], 3e-3, 0.5e-3);
  energy(runs[2], 5e-3, 2e-3);
  const std::vector<Claim>& claims = paper_claims();
  ASSERT_EQ(claims[17].id, "P18");
  const auto measured = measure_claims(claims, runs);
  EXPECT_DOUBLE_EQ(measured[17][0].mean, 0.5);   // oo-vr links
  EXPECT_DOUBLE_EQ(measured[17][1].mean, 2.0);   // object links
  EXPECT_DOUBLE_EQ(measured[17][2].mean, 0.75);  // oo-vr memory
  EXPECT_TRUE(judge_claims(claims, measured)[17][0].holds);
  EXPECT_TRUE(judge_claims(claims, measured)[17][1].holds);
  energy(runs[1], 5e-3, 1.5e-3);  // now more than the baseline's (the first rows are read)
  runs[1].metrics.erase(runs[1].metrics.begin() + 2, runs[1].metrics.begin() + 4);
  const auto more = measure_claims(claims, runs);
  EXPECT_DOUBLE_EQ(more[17][0].mean, 1.5);
  EXPECT_FALSE(judge_claims(claims, more)[17][0].holds);
  EXPECT_FALSE(judge_claims(claims, more)[17][1].holds);
  // A run stored before oovr counted energy has none to compare.
  runs[0].metrics.resize(2);
  EXPECT_TRUE(measure_claims(claims, runs)[17][0].per.empty());
}

}  // namespace
}  // namespace oovr
