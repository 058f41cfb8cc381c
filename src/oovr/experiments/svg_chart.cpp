#include "oovr/experiments/svg_chart.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <utility>

#include "oovr/core/error.h"
#include "oovr/core/host.h"
#include "oovr/core/text.h"
#include "oovr/schemes/i_scheme.h"

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

// matplotlib's tab20 in the report's order (report.py, PALETTE): the ten
// dark shades, then the ten light ones, so that up to ten series never
// share a hue's shade and twenty never share a colour.
const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
                          "#7f7f7f", "#bcbd22", "#17becf", "#aec7e8", "#ffbb78", "#98df8a", "#ff9896",
                          "#c5b0d5", "#c49c94", "#f7b6d2", "#c7c7c7", "#dbdb8d", "#9edae5"};
constexpr size_t kPaletteSize = sizeof kPalette / sizeof kPalette[0];

// A series' colour: its scheme's in every figure when every series is a
// scheme (the report's too), else its place in the chart.
std::string series_colour(const std::vector<std::string>& series, size_t k) {
  const auto order = schemes_in_order();
  for (const auto& name : series)
    if (std::find(order.begin(), order.end(), name) == order.end()) return kPalette[k % kPaletteSize];
  return scheme_colour(series[k]);
}

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
                     top + 18 * double(k), series_colour(series, k), x + 17, top + 18 * double(k) + 10, xml(series[k]));
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

std::string scheme_colour(const std::string& scheme) {
  const auto order = schemes_in_order();
  const auto at = std::find(order.begin(), order.end(), scheme);
  if (at != order.end()) return kPalette[size_t(at - order.begin()) % kPaletteSize];
  // Another name (a Python scheme's): a stable colour of its bytes.
  size_t sum = 0;
  for (unsigned char c : scheme) sum += c;
  return kPalette[(order.size() + sum * 7) % kPaletteSize];
}

std::string bar_chart(const std::string& title, const std::string& y_label, const std::vector<std::string>& groups,
                      const std::vector<std::string>& series, const std::vector<std::vector<double>>& values, double ref,
                      const std::vector<std::vector<std::pair<double, double>>>& spread, const std::string& spread_label) {
  const double w = 920, h = 440, left = 90, right = 160, top = 40, bottom = 100;
  // The axis holds the whiskers' tops too.
  double highest = finite_max(values, ref);
  for (const auto& row : spread)
    for (const auto& [lo, hi] : row)
      if (std::isfinite(hi)) highest = std::max(highest, hi);
  // (Not a structured binding: Clang 14 cannot capture one in the lambdas below.)
  const std::pair<double, double> axis = nice_axis(highest * 1.05);
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
          x, y(v), bw * 0.95, top + ph - y(v), series_colour(series, k), xml(groups[g]), xml(series[k]), v);
      if (g < spread.size() && k < spread[g].size() && std::isfinite(spread[g][k].first) && std::isfinite(spread[g][k].second)) {
        const double cx = x + bw * 0.475, lo = spread[g][k].first, hi = spread[g][k].second;
        s += fmt::format(
            "<path d=\"M{0:.1f} {1:.1f}V{2:.1f}M{3:.1f} {1:.1f}H{4:.1f}M{3:.1f} {2:.1f}H{4:.1f}\" stroke=\"black\" "
            "stroke-width=\"1\"><title>{5} {6}: {7:.3f} to {8:.3f}</title></path>\n",
            cx, y(hi), y(lo), cx - bw * 0.2, cx + bw * 0.2, xml(groups[g]), xml(series[k]), lo, hi);
      }
    }
    s += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"end\" transform=\"rotate(-30 {:.1f} {})\">{}</text>\n",
                     left + gw * (double(g) + 0.5), top + ph + 16, left + gw * (double(g) + 0.5), top + ph + 16, xml(groups[g]));
  }
  s += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"black\" stroke-dasharray=\"4 3\"/>\n", left,
                   left + pw, y(ref), y(ref));
  s += svg_y_label(top, ph, y_label) + svg_legend(left + pw + 15, top, series);
  if (!spread.empty() && !spread_label.empty())
    s += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"10\">{}</text>\n", left + pw + 15,
                     top + 18 * double(series.size()) + 14, xml(spread_label));
  return s + "</svg>\n";
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
    s += fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>\n", pts, series_colour(series, k));
    for (size_t i = 0; i < xs.size(); ++i)
      if (std::isfinite(values[k][i]))
        s += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3\" fill=\"{}\"><title>{} {}: {:.3f}</title></circle>\n",
                         X(xs[i]), Y(values[k][i]), series_colour(series, k), xml(series[k]), xml(x_names[i]), values[k][i]);
  }
  return s + "</svg>\n";
}

size_t write_pdf_and_png(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<fs::path> charts;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".svg") charts.push_back(e.path());
  if (ec) throw Error("cannot list the charts in '" + dir + "': " + ec.message());
  std::sort(charts.begin(), charts.end());
  for (const fs::path& svg : charts)
    for (const auto& [format, ext] : {std::pair{"pdf", ".pdf"}, std::pair{"png", ".png"}}) {
      const std::string in = svg.string(), out = fs::path(svg).replace_extension(ext).string();
      // PNG at twice the SVG's size: sharp on a slide or a high-density screen.
      std::string said;
      const int rc = run_command(
          {"rsvg-convert", "--format", format, "--zoom", std::string(format) == "png" ? "2" : "1", "--output", out, in}, said);
      if (rc == 127)
        throw Error(
            "rsvg-convert is not installed, so the charts are SVG only (librsvg2-bin; scripts/install-deps.sh installs it)");
      if (rc != 0)
        throw Error("rsvg-convert could not convert '" + in + "' to " + format + ": " + printable(said.substr(0, 4096)));
    }
  return charts.size();
}

}  // namespace oovr
