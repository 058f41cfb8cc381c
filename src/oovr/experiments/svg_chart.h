// The comparison document's charts (`oovr paper`: Figures 15 to 18 and
// OO-VR's copies), as SVG written by hand: a chart is a few rectangles,
// lines and labels, and SVG needs no plotting library (the report's plots,
// which a reader may redraw, are matplotlib's: report.py). Every text is
// escaped for XML.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace oovr {

// A scheme's colour in every figure oovr draws (these charts and the
// report's, which reads it from claims.json): matplotlib's tab20 by the
// registered order (dark shades first), another name by a stable hash of
// its bytes. A chart whose series are all schemes colours them so; others
// (categories, capacities) by their place.
std::string scheme_colour(const std::string& scheme);

// Grouped bars: one group per label, one bar per series (values[group]
// [series], NaN for none); a dashed line at `ref`. `spread`, when given
// (the same shape, each a low and a high), draws a whisker on each bar
// from low to high (NaNs: none) and `spread_label` says what it is under
// the legend.
std::string bar_chart(const std::string& title, const std::string& y_label, const std::vector<std::string>& groups,
                      const std::vector<std::string>& series, const std::vector<std::vector<double>>& values, double ref,
                      const std::vector<std::vector<std::pair<double, double>>>& spread = {},
                      const std::string& spread_label = "");

// Lines over x values (log scale when `log_x`), one per series
// (values[series][x], NaN for none), each x named by x_names.
std::string line_chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                       const std::vector<double>& xs, const std::vector<std::string>& x_names,
                       const std::vector<std::string>& series, const std::vector<std::vector<double>>& values, bool log_x);

// Each chart (.svg) in `dir` also as PDF and PNG beside it, for a paper or
// a slide, by librsvg's rsvg-convert (scripts/install-deps.sh installs it).
// Returns how many charts were converted; throws Error naming the chart
// when rsvg-convert is missing or fails on one.
size_t write_pdf_and_png(const std::string& dir);

}  // namespace oovr
