// The paper's claims as data (experiments/paper-claims.toml).
#include <gtest/gtest.h>

#include <set>

#include "oovr/experiments/claims.h"
#include "oovr/schemes/i_scheme.h"
#include "test_util.h"

namespace oovr {
namespace {

using test::message_of;

TEST(Claims, TheCarriedFileHoldsP1ToP16WithKnownSchemesAndKeys) {
  const auto& claims = paper_claims();
  ASSERT_EQ(claims.size(), 16u);
  std::set<std::string> ids;
  for (const Claim& c : claims) {
    ids.insert(c.id);
    for (const ClaimValue& v : c.values) {
      EXPECT_TRUE(Schemes::find(v.scheme)) << c.id << ": " << v.scheme;
      EXPECT_TRUE(Schemes::find(v.against)) << c.id << ": " << v.against;
    }
  }
  for (int i = 1; i <= 16; ++i) {
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
  // A setting no component takes is an error naming the claim.
  const auto bad = parse_claims(head + value + "measure = 'speedup'\nset = { 'link.bandwith' = '1TBps' }\n", "c.toml");
  EXPECT_NE(message_of([&] { (void)resolved_claims_json(bad); }).find("P1 (l)"), std::string::npos);
}

}  // namespace
}  // namespace oovr
