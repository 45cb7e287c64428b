#include "nav/station/error_plot.hpp"

#include <algorithm>
#include <cmath>

#include "nav/station/format_numbers.hpp"

namespace nav::station {

namespace {

constexpr double kWidth = 900.0, kHeight = 420.0;
constexpr double kLeft = 70.0, kRight = 220.0, kTop = 40.0, kBottom = 50.0;  // margins

/// A "nice" tick step (1, 2 or 5 times a power of ten) for about `count` ticks over `span`.
double tick_step(double span, int count) {
  const double raw = span / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) return m * power;
  return 10.0 * power;
}

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text)
    out += c == '<'   ? std::string("&lt;")
           : c == '>' ? std::string("&gt;")
           : c == '&' ? std::string("&amp;")
                      : std::string(1, c);
  return out;
}

}  // namespace

std::string error_plot_svg(const std::string& title, const std::vector<PlotSeries>& series) {
  double x_max = 1e-9, y_max = 1e-9;
  for (const PlotSeries& s : series) {
    for (const double x : s.x) x_max = std::max(x_max, x);
    for (const double y : s.y) y_max = std::max(y_max, y);
  }
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const auto px = [&](double x) { return kLeft + plot_w * x / x_max; };
  const auto py = [&](double y) { return kTop + plot_h * (1.0 - std::min(y, y_max) / y_max); };
  std::string svg = format_numbers(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" "
      "font-size=\"12\">\n",
      kWidth, kHeight);
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += format_numbers("<text x=\"%.1f\" y=\"24\" font-size=\"15\">", kLeft) + escape(title) + "</text>\n";
  const double xs = tick_step(x_max, 10), ys = tick_step(y_max, 6);
  for (double x = 0.0; x <= x_max + 1e-9; x += xs)
    svg += format_numbers("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>", px(x), kTop, px(x),
                          kTop + plot_h) +
           format_numbers("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n", px(x), kTop + plot_h + 16.0,
                          x);
  for (double y = 0.0; y <= y_max + 1e-9; y += ys)
    svg += format_numbers("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>", kLeft, py(y),
                          kLeft + plot_w, py(y)) +
           format_numbers("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", kLeft - 6.0, py(y) + 4.0, y);
  svg += format_numbers("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"black\"/>\n",
                        kLeft, kTop, plot_w, plot_h);
  svg += format_numbers("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">time (s)</text>\n", kLeft + 0.5 * plot_w,
                        kHeight - 10.0);
  svg += format_numbers(
      "<text x=\"18\" y=\"%.1f\" text-anchor=\"middle\" transform=\"rotate(-90 18 %.1f)\">error (mm)</text>\n",
      kTop + 0.5 * plot_h, kTop + 0.5 * plot_h);
  double legend_y = kTop + 10.0;
  for (const PlotSeries& s : series) {
    svg += "<polyline fill=\"none\" stroke-width=\"1.2\" stroke=\"" + s.colour + "\"" +
           (s.dashed ? " stroke-dasharray=\"5,3\"" : "") + " points=\"";
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      svg += format_numbers("%.1f,%.1f ", px(s.x[i]), py(s.y[i]));
    svg += "\"/>\n";
    svg += format_numbers("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke-width=\"2\" ",
                          kWidth - kRight + 12.0, legend_y, kWidth - kRight + 40.0, legend_y) +
           "stroke=\"" + s.colour + "\"" + (s.dashed ? " stroke-dasharray=\"5,3\"" : "") + "/>";
    svg += format_numbers("<text x=\"%.1f\" y=\"%.1f\">", kWidth - kRight + 46.0, legend_y + 4.0) + escape(s.name) +
           "</text>\n";
    legend_y += 20.0;
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace nav::station
