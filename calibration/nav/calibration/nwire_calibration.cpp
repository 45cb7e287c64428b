#include "nav/calibration/nwire_calibration.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <string>

namespace nav::calibration {
namespace {

constexpr std::size_t kBootstrapFits = 200;

/// Each frame's segmented lines (nullopt where the phantom was not found).
using Segmentation = std::vector<std::optional<std::vector<NWireLine>>>;

Segmentation segment(const std::vector<TrackedImage>& frames, std::size_t patterns,
                     const NWireSegmentationOptions& options) {
  Segmentation lines;
  for (const TrackedImage& frame : frames) {
    lines.push_back(find_nwire_dots(frame.pixels, frame.width_px, frame.height_px, patterns, options));
  }
  return lines;
}

NWirePoints points_of(const std::vector<TrackedImage>& frames, const Segmentation& lines, const NWirePhantom& phantom,
                      const NWireCorrespondence& correspondence) {
  NWirePoints result;
  result.frames_total = frames.size();
  const std::size_t patterns = phantom.patterns.size();
  for (std::size_t f = 0; f < frames.size(); ++f) {
    if (!lines[f]) continue;
    ++result.frames_segmented;
    const Transform probe_from_phantom =
        frames[f].tracker_from_probe.inverse() * frames[f].tracker_from_reference * phantom.reference_from_phantom;
    for (std::size_t p = 0; p < patterns; ++p) {
      const NWireLine& line = (*lines[f])[correspondence.lines_bottom_up ? patterns - 1 - p : p];
      const Eigen::Vector2d& first = correspondence.wires_right_left ? line[2] : line[0];
      const Eigen::Vector2d& last = correspondence.wires_right_left ? line[0] : line[2];
      const Eigen::Vector3d in_phantom = middle_wire_point(phantom.patterns[p], first, line[1], last);
      result.points.push_back({line[1], probe_from_phantom * in_phantom});
    }
  }
  return result;
}

/// The bootstrap uncertainty of `calibration` (NWireCalibration::uncertainty_m), from its
/// points (patterns points a frame, frame after frame) on images of width x height pixels.
double bootstrap_uncertainty_m(const ProbeCalibration& calibration, const std::vector<ImageProbePoint>& points,
                               std::size_t patterns, int width_px, int height_px, std::size_t fits) {
  const std::size_t frames = points.size() / patterns;
  const std::array<Eigen::Vector2d, 5> corners{
      Eigen::Vector2d(0, 0), Eigen::Vector2d(width_px - 1, 0), Eigen::Vector2d(0, height_px - 1),
      Eigen::Vector2d(width_px - 1, height_px - 1), Eigen::Vector2d(0.5 * (width_px - 1), 0.5 * (height_px - 1))};
  std::mt19937_64 random(20111713);
  std::uniform_int_distribution<std::size_t> frame(0, frames - 1);
  double sum_squares = 0.0;
  std::size_t done = 0;
  std::vector<ImageProbePoint> drawn;
  for (std::size_t fit = 0; fit < fits; ++fit) {
    drawn.clear();
    for (std::size_t f = 0; f < frames; ++f) {
      const std::size_t from = frame(random) * patterns;
      drawn.insert(drawn.end(), points.begin() + static_cast<std::ptrdiff_t>(from),
                   points.begin() + static_cast<std::ptrdiff_t>(from + patterns));
    }
    const auto again = fit_probe_calibration(drawn);
    if (!again) continue;
    double largest = 0.0;
    for (const Eigen::Vector2d& corner : corners)
      largest = std::max(largest, (probe_point(again.value(), corner) - probe_point(calibration, corner)).norm());
    sum_squares += largest * largest;
    ++done;
  }
  return done > 0 ? std::sqrt(sum_squares / static_cast<double>(done)) : 0.0;
}

}  // namespace

NWirePoints nwire_points(const std::vector<TrackedImage>& frames, const NWirePhantom& phantom,
                         const NWireCorrespondence& correspondence, const NWireSegmentationOptions& segmentation) {
  return points_of(frames, segment(frames, phantom.patterns.size(), segmentation), phantom, correspondence);
}

Result<NWireCalibration> nwire_calibration(const std::vector<TrackedImage>& frames, const NWirePhantom& phantom,
                                           std::size_t min_frames, const NWireSegmentationOptions& segmentation) {
  const Segmentation lines = segment(frames, phantom.patterns.size(), segmentation);
  std::optional<NWireCalibration> best;
  std::vector<ImageProbePoint> best_points;
  for (const bool bottom_up : {false, true}) {
    for (const bool right_left : {false, true}) {
      const NWireCorrespondence correspondence{bottom_up, right_left};
      const NWirePoints points = points_of(frames, lines, phantom, correspondence);
      if (points.frames_segmented < min_frames) {
        return Error{.message = "the N-wire phantom was found in " + std::to_string(points.frames_segmented) + " of " +
                                std::to_string(points.frames_total) + " frames (at least " +
                                std::to_string(min_frames) + " needed)",
                     .field = "frames"};
      }
      auto fit = fit_probe_calibration(points.points);
      if (!fit) return fit.error();
      if (!best || fit.value().rms_residual_m < best->calibration.rms_residual_m) {
        best = NWireCalibration{fit.value(), correspondence, points.frames_segmented, points.frames_total};
        best_points = points.points;
      }
    }
  }
  best->bootstrap_fits = kBootstrapFits;
  best->uncertainty_m = bootstrap_uncertainty_m(best->calibration, best_points, phantom.patterns.size(),
                                                frames.front().width_px, frames.front().height_px, kBootstrapFits);
  return *best;
}

}  // namespace nav::calibration
