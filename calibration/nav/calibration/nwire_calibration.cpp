#include "nav/calibration/nwire_calibration.hpp"

#include <optional>
#include <string>

namespace nav::calibration {
namespace {

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

}  // namespace

NWirePoints nwire_points(const std::vector<TrackedImage>& frames, const NWirePhantom& phantom,
                         const NWireCorrespondence& correspondence, const NWireSegmentationOptions& segmentation) {
  return points_of(frames, segment(frames, phantom.patterns.size(), segmentation), phantom, correspondence);
}

Result<NWireCalibration> nwire_calibration(const std::vector<TrackedImage>& frames, const NWirePhantom& phantom,
                                           std::size_t min_frames, const NWireSegmentationOptions& segmentation) {
  const Segmentation lines = segment(frames, phantom.patterns.size(), segmentation);
  std::optional<NWireCalibration> best;
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
      }
    }
  }
  return *best;
}

}  // namespace nav::calibration
