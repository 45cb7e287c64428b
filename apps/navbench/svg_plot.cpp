#include "svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace navbench {
namespace {

constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                    "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};
constexpr int kColourCount = 10;

std::string format(const char* pattern, auto... values) {
  char text[512];
  std::snprintf(text, sizeof(text), pattern, values...);
  return text;
}

/// `text` with the XML special characters escaped.
std::string xml(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

/// The marker of group number `g` centred at (x, y).
std::string marker(std::size_t g, double x, double y, const char* fill, const char* stroke, const std::string& title) {
  const std::string inner = "<title>" + xml(title) + "</title>";
  switch (g % 3) {
    case 0:
      return format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"%s\" stroke=\"%s\">", x, y, fill, stroke) + inner +
             "</circle>\n";
    case 1:
      return format("<rect x=\"%.1f\" y=\"%.1f\" width=\"9\" height=\"9\" fill=\"%s\" stroke=\"%s\">", x - 4.5, y - 4.5,
                    fill, stroke) +
             inner + "</rect>\n";
    default:
      return format("<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"%s\" stroke=\"%s\">", x, y - 6, x - 5.5,
                    y + 4, x + 5.5, y + 4, fill, stroke) +
             inner + "</polygon>\n";
  }
}

template <typename T>
std::vector<T> unique_in_order(const std::vector<T>& items) {
  std::vector<T> out;
  for (const T& item : items)
    if (std::find(out.begin(), out.end(), item) == out.end()) out.push_back(item);
  return out;
}

}  // namespace

std::vector<std::size_t> pareto_front(const std::vector<PlotPoint>& points, const std::string& group) {
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].group != group) continue;
    bool dominated = false;
    for (std::size_t j = 0; j < points.size() && !dominated; ++j)
      dominated = j != i && points[j].group == group && points[j].x <= points[i].x && points[j].y <= points[i].y &&
                  (points[j].x < points[i].x || points[j].y < points[i].y);
    if (!dominated) front.push_back(i);
  }
  std::sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) { return points[a].x < points[b].x; });
  return front;
}

std::string log_log_svg(const std::vector<PlotPoint>& points, const PlotLabels& labels) {
  const double width = 960, height = 640, left = 90, bottom = 60, right = 280, top = 40;
  double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
  for (const PlotPoint& p : points) {
    x_lo = std::min(x_lo, std::floor(std::log10(p.x)));
    x_hi = std::max(x_hi, std::ceil(std::log10(p.x)));
    y_lo = std::min(y_lo, std::floor(std::log10(p.y)));
    y_hi = std::max(y_hi, std::ceil(std::log10(p.y)));
  }
  if (points.empty()) x_lo = y_lo = 0, x_hi = y_hi = 1;
  if (x_hi <= x_lo) x_hi = x_lo + 1;
  if (y_hi <= y_lo) y_hi = y_lo + 1;
  const auto px = [&](double x) { return left + (std::log10(x) - x_lo) / (x_hi - x_lo) * (width - left - right); };
  const auto py = [&](double y) { return top + (y_hi - std::log10(y)) / (y_hi - y_lo) * (height - top - bottom); };

  std::string svg = format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" "
      "font-size=\"12\">\n",
      width, height);
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += format("<text x=\"%.1f\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">", (left + width - right) / 2) +
         xml(labels.title) + "</text>\n";
  for (int d = static_cast<int>(x_lo); d <= static_cast<int>(x_hi); ++d)
    svg += format(
        "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
        "text-anchor=\"middle\">1e%d</text>\n",
        px(std::pow(10.0, d)), top, px(std::pow(10.0, d)), height - bottom, px(std::pow(10.0, d)), height - bottom + 18,
        d);
  for (int d = static_cast<int>(y_lo); d <= static_cast<int>(y_hi); ++d)
    svg += format(
        "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
        "text-anchor=\"end\">1e%d</text>\n",
        left, py(std::pow(10.0, d)), width - right, py(std::pow(10.0, d)), left - 6, py(std::pow(10.0, d)) + 4, d);
  svg += format("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">", (left + width - right) / 2, height - 20) +
         xml(labels.x) + "</text>\n";
  svg += format("<text x=\"18\" y=\"%.1f\" transform=\"rotate(-90 18 %.1f)\" text-anchor=\"middle\">",
                (top + height - bottom) / 2, (top + height - bottom) / 2) +
         xml(labels.y) + "</text>\n";

  std::vector<std::string> keys, groups;
  for (const PlotPoint& p : points) keys.push_back(p.colour_key), groups.push_back(p.group);
  keys = unique_in_order(keys);
  groups = unique_in_order(groups);
  const auto colour_of = [&](const std::string& key) {
    return kColours[static_cast<std::size_t>(std::find(keys.begin(), keys.end(), key) - keys.begin()) % kColourCount];
  };
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<std::size_t> front = pareto_front(points, groups[g]);
    std::string line;
    for (const std::size_t i : front) line += format("%.1f,%.1f ", px(points[i].x), py(points[i].y));
    svg += "<polyline class=\"pareto\" points=\"" + line +
           "\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\"/>\n";
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (points[i].group != groups[g]) continue;
      const bool on_front = std::find(front.begin(), front.end(), i) != front.end();
      svg += marker(g, px(points[i].x), py(points[i].y), colour_of(points[i].colour_key), on_front ? "black" : "none",
                    points[i].title + (on_front ? " (Pareto front)" : ""));
    }
  }
  double y = top + 10;
  for (const std::string& key : keys) {
    svg += format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"%s\"/><text x=\"%.1f\" y=\"%.1f\">",
                  width - right + 20, y, colour_of(key), width - right + 32, y + 4) +
           xml(key) + "</text>\n";
    y += 18;
  }
  y += 10;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    svg += marker(g, width - right + 20, y, "#888", "none", groups[g]);
    svg += format("<text x=\"%.1f\" y=\"%.1f\">", width - right + 32, y + 4) + xml(groups[g]) + "</text>\n";
    y += 18;
  }
  svg +=
      format("<text x=\"%.1f\" y=\"%.1f\">dashed, outlined: Pareto front per mesh</text>\n", width - right + 20, y + 8);
  return svg + "</svg>\n";
}

}  // namespace navbench
