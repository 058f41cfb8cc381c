// The comparison document's charts (`oovr paper`: Figures 15 to 18 and
// OO-VR's copies), as SVG written by hand: a chart is a few rectangles,
// lines and labels, and SVG needs no plotting library (the report's plots,
// which a reader may redraw, are matplotlib's: report.py). Every text is
// escaped for XML.
#pragma once

#include <string>
#include <vector>

namespace oovr {

// Grouped bars: one group per label, one bar per series (values[group]
// [series], NaN for none); a dashed line at `ref`.
std::string bar_chart(const std::string& title, const std::string& y_label, const std::vector<std::string>& groups,
                      const std::vector<std::string>& series, const std::vector<std::vector<double>>& values, double ref);

// Lines over x values (log scale when `log_x`), one per series
// (values[series][x], NaN for none), each x named by x_names.
std::string line_chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                       const std::vector<double>& xs, const std::vector<std::string>& x_names,
                       const std::vector<std::string>& series, const std::vector<std::vector<double>>& values, bool log_x);

}  // namespace oovr
