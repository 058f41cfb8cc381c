#include "oovr/experiments/svg_chart.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

namespace oovr {

namespace {

std::string xml(const std::string& s) {
  std::string r;
  for (char c : s) {
    if (c == '<') r += "&lt;";
    else if (c == '>') r += "&gt;";
    else if (c == '&') r += "&amp;";
    else r += c;
  }
  return r;
}

// A round axis top and its tick step (1, 2 or 5 times a power of ten).
std::pair<double, double> nice_axis(double vmax) {
  if (!(vmax > 0)) return {1, 0.2};
  const double raw = vmax / 5, p = std::pow(10.0, std::floor(std::log10(raw)));
  double step = p;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) {
      step = m * p;
      break;
    }
  return {std::ceil(vmax / step) * step, step};
}

const char* kColours[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948",
                          "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac", "#1f77b4"};

// The parts both charts share: the canvas and title, the horizontal grid
// with its tick values, the y-axis label and the legend.
std::string svg_open(double w, double h, double left, const std::string& title) {
  return fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{}\" y=\"22\" font-size=\"15\">{}</text>\n",
      w, h, left, xml(title));
}
std::string svg_grid(double left, double pw, double vmax, double step, const std::function<double(double)>& y) {
  std::string s;
  for (double v = 0; v <= vmax * (1 + 1e-9); v += step) {
    s += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>\n", left, left + pw, y(v), y(v));
    s += fmt::format("<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{:g}</text>\n", left - 5, y(v) + 4, v);
  }
  return s;
}
std::string svg_y_label(double top, double ph, const std::string& label) {
  return fmt::format("<text x=\"14\" y=\"{}\" transform=\"rotate(-90 14 {})\" text-anchor=\"middle\">{}</text>\n", top + ph / 2,
                     top + ph / 2, xml(label));
}
std::string svg_legend(double x, double top, const std::vector<std::string>& series) {
  std::string s;
  for (size_t k = 0; k < series.size(); ++k)
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"12\" fill=\"{}\"/><text x=\"{}\" y=\"{}\">{}</text>\n", x,
                     top + 18 * double(k), kColours[k % 11], x + 17, top + 18 * double(k) + 10, xml(series[k]));
  return s;
}

// The largest finite value, at least `floor`.
double finite_max(const std::vector<std::vector<double>>& values, double floor) {
  for (const auto& row : values)
    for (double v : row)
      if (std::isfinite(v)) floor = std::max(floor, v);
  return floor;
}

}  // namespace

std::string bar_chart(const std::string& title, const std::string& y_label, const std::vector<std::string>& groups,
                      const std::vector<std::string>& series, const std::vector<std::vector<double>>& values, double ref) {
  const double w = 920, h = 440, left = 90, right = 160, top = 40, bottom = 100;
  // (Not a structured binding: Clang 14 cannot capture one in the lambdas below.)
  const std::pair<double, double> axis = nice_axis(finite_max(values, ref) * 1.05);
  const double vmax = axis.first, step = axis.second;
  const double pw = w - left - right, ph = h - top - bottom;
  const auto y = [&](double v) { return top + ph - v / vmax * ph; };
  std::string s = svg_open(w, h, left, title) + svg_grid(left, pw, vmax, step, y);
  const double gw = pw / double(std::max<size_t>(1, groups.size()));
  const double bw = gw * 0.8 / double(std::max<size_t>(1, series.size()));
  for (size_t g = 0; g < groups.size(); ++g) {
    for (size_t k = 0; k < series.size(); ++k) {
      const double v = values[g][k];
      if (!std::isfinite(v)) continue;
      const double x = left + gw * double(g) + gw * 0.1 + bw * double(k);
      s += fmt::format(
          "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\"><title>{} {}: {:.3f}</title></rect>\n",
          x, y(v), bw * 0.95, top + ph - y(v), kColours[k % 11], xml(groups[g]), xml(series[k]), v);
    }
    s += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"end\" transform=\"rotate(-30 {:.1f} {})\">{}</text>\n",
                     left + gw * (double(g) + 0.5), top + ph + 16, left + gw * (double(g) + 0.5), top + ph + 16, xml(groups[g]));
  }
  s += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"black\" stroke-dasharray=\"4 3\"/>\n", left,
                   left + pw, y(ref), y(ref));
  return s + svg_y_label(top, ph, y_label) + svg_legend(left + pw + 15, top, series) + "</svg>\n";
}

std::string line_chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                       const std::vector<double>& xs, const std::vector<std::string>& x_names,
                       const std::vector<std::string>& series, const std::vector<std::vector<double>>& values, bool log_x) {
  const double w = 620, h = 400, left = 60, right = 130, top = 40, bottom = 50;
  const std::pair<double, double> axis = nice_axis(finite_max(values, 0) * 1.05);
  const double vmax = axis.first, step = axis.second;
  const double pw = w - left - right, ph = h - top - bottom;
  const auto fx = [&](double x) { return log_x ? std::log(x) : x; };
  const double x0 = fx(xs.front()), x1 = fx(xs.back());
  const auto X = [&](double x) { return left + (fx(x) - x0) / (x1 - x0) * pw; };
  const auto Y = [&](double v) { return top + ph - v / vmax * ph; };
  std::string s = svg_open(w, h, left, title) + svg_grid(left, pw, vmax, step, Y);
  for (size_t i = 0; i < xs.size(); ++i)
    s += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", X(xs[i]), top + ph + 16, xml(x_names[i]));
  s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", left + pw / 2, top + ph + 36, xml(x_label));
  s += svg_y_label(top, ph, y_label) + svg_legend(left + pw + 15, top, series);
  for (size_t k = 0; k < series.size(); ++k) {
    std::string pts;
    for (size_t i = 0; i < xs.size(); ++i)
      if (std::isfinite(values[k][i])) pts += fmt::format("{:.1f},{:.1f} ", X(xs[i]), Y(values[k][i]));
    s += fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>\n", pts, kColours[k % 11]);
    for (size_t i = 0; i < xs.size(); ++i)
      if (std::isfinite(values[k][i]))
        s += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3\" fill=\"{}\"><title>{} {}: {:.3f}</title></circle>\n",
                         X(xs[i]), Y(values[k][i]), kColours[k % 11], xml(series[k]), xml(x_names[i]), values[k][i]);
  }
  return s + "</svg>\n";
}

}  // namespace oovr
