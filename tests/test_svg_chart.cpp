// The paper's charts (experiments/svg_chart.h): a scheme has one colour in
// every figure, the report's included.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "oovr/experiments/svg_chart.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {
namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(SvgChart, ASchemeHasOneColourInEveryChart) {
  // The registered schemes, in order, take tab20's colours, dark shades
  // first (the report's palette): the paper's schemes first.
  const auto order = schemes_in_order();
  ASSERT_GE(order.size(), 3u);
  ASSERT_EQ(order[0], "baseline");
  EXPECT_EQ(scheme_colour("baseline"), "#1f77b4");
  std::set<std::string> seen;
  for (size_t k = 0; k < order.size() && k < 20; ++k) EXPECT_TRUE(seen.insert(scheme_colour(order[k])).second) << order[k];
  EXPECT_EQ(scheme_colour("my-python-scheme"), scheme_colour("my-python-scheme"));
  // oo-vr is drawn in its colour whatever the chart's other series.
  const std::string oo = scheme_colour("oo-vr");
  const std::string bars = bar_chart("t", "y", {"a", "b"}, {"object", "oo-vr"}, {{1, 2}, {1, 3}}, 1);
  const std::string lines =
      line_chart("t", "x", "y", {1, 2}, {"1", "2"}, {"oo-vr", "baseline", "afr"}, {{1, 2}, {1, 1}, {0.5, 0.5}}, false);
  EXPECT_EQ(count(bars, "fill=\"" + oo + "\""), 3u);  // two bars and the legend
  EXPECT_GE(count(lines, "stroke=\"" + oo + "\""), 1u);
  EXPECT_EQ(count(lines, "fill=\"" + oo + "\""), 3u);  // two points and the legend
  // Series that are not schemes (categories) take the palette in order.
  const std::string cats = bar_chart("t", "y", {"a"}, {"texture", "depth"}, {{1, 2}}, 0);
  EXPECT_EQ(count(cats, "fill=\"#1f77b4\""), 2u);
  EXPECT_EQ(count(cats, "fill=\"#ff7f0e\""), 2u);
}

// Figure 15's whiskers: one per bar with a spread, from its low to its
// high, within the axis; none where the spread is unknown.
TEST(SvgChart, BarsCarryTheirSpreadAsWhiskers) {
  const std::string plain = bar_chart("t", "y", {"a", "b"}, {"object", "oo-vr"}, {{1, 2}, {1, 3}}, 1);
  EXPECT_EQ(count(plain, "<path"), 0u);
  const double nan = std::nan("");
  const std::string whiskers = bar_chart("t", "y", {"a", "b"}, {"object", "oo-vr"}, {{1, 2}, {1, 3}}, 1,
                                         {{{0.9, 1.1}, {1.5, 5.0}}, {{nan, nan}}}, "whiskers: frames' range");
  EXPECT_EQ(count(whiskers, "<path"), 2u);
  EXPECT_NE(whiskers.find("oo-vr: 1.500 to 5.000"), std::string::npos);
  EXPECT_NE(whiskers.find("whiskers: frames' range"), std::string::npos);
  // The axis reaches past the highest whisker (5: up to 6), not only the highest bar (3: up to 4).
  EXPECT_NE(whiskers.find(">6</text>"), std::string::npos);
  EXPECT_EQ(plain.find(">6</text>"), std::string::npos);
}

}  // namespace
}  // namespace oovr
