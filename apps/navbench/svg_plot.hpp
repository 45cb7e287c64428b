#pragma once
// A hand-written SVG scatter plot on log-log axes with the Pareto front of each series group
// highlighted: what navbench tradeoff draws (error against step time).
#include <string>
#include <vector>

namespace navbench {

/// One point: its position (both positive), its colour key and marker group, and a tooltip.
struct PlotPoint {
  double x = 0.0, y = 0.0;
  std::string colour_key;  ///< points of one key share a colour (the legend lists the keys)
  std::string group;       ///< points of one group share a marker and a Pareto front
  std::string title;
};

/// Axis titles of the plot.
struct PlotLabels {
  std::string x, y, title;
};

/// Indices of the points of `points` on the Pareto front of their group (no other point of the
/// group has both x and y smaller or equal, one of them strictly), by increasing x.
std::vector<std::size_t> pareto_front(const std::vector<PlotPoint>& points, const std::string& group);

/// The SVG text of a log-log scatter of `points`, with each group's Pareto front drawn as a
/// line through its points (outlined in black).
std::string log_log_svg(const std::vector<PlotPoint>& points, const PlotLabels& labels);

}  // namespace navbench
