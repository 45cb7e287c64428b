#pragma once
// A hand-written SVG line plot of error curves over time (no plotting library): axes with
// labelled ticks, one polyline per series, a legend. Init/report-time code.
#include <string>
#include <vector>

namespace nav::station {

/// One curve: its points (x, y) and how it is drawn.
struct PlotSeries {
  std::string name;
  std::string colour;  ///< an SVG colour, e.g. "#1f77b4"
  bool dashed = false;
  std::vector<double> x, y;
};

/// The SVG document of `series` (x: time in seconds, y: error in millimetres).
std::string error_plot_svg(const std::string& title, const std::vector<PlotSeries>& series);

}  // namespace nav::station
