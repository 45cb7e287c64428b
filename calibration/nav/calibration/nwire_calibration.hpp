#pragma once
// Probe spatial calibration with an N-wire phantom: segment the wire dots in each tracked
// frame, place each pattern's middle-wire point in the phantom, carry it into the probe frame
// through the tracked reference and probe poses and the phantom registration, and fit the
// image-to-probe calibration to all those points. Which image line is which pattern, and
// which way the wires run across the image, is settled by the best fit of the four choices.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nav/calibration/nwire_phantom.hpp"
#include "nav/calibration/nwire_segmentation.hpp"
#include "nav/calibration/probe_calibration.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// One tracked frame of a calibration recording (pixels borrowed, 8-bit row-major).
struct TrackedImage {
  const std::uint8_t* pixels = nullptr;
  int width_px = 0;
  int height_px = 0;
  Transform tracker_from_probe = Transform::Identity();
  Transform tracker_from_reference = Transform::Identity();
};

/// How image lines and dots correspond to the phantom's patterns and wires.
struct NWireCorrespondence {
  bool lines_bottom_up = false;   ///< the first pattern is the lowest image line
  bool wires_right_left = false;  ///< each pattern's first wire is its rightmost dot
};

/// The middle-wire points of a recording, as pixel / probe-frame pairs.
struct NWirePoints {
  std::vector<ImageProbePoint> points;
  std::size_t frames_segmented = 0;
  std::size_t frames_total = 0;
};

/// Segments every frame and gives the middle-wire points under `correspondence`.
NWirePoints nwire_points(const std::vector<TrackedImage>& frames, const NWirePhantom& phantom,
                         const NWireCorrespondence& correspondence, const NWireSegmentationOptions& segmentation = {});

/// The result of an N-wire calibration.
struct NWireCalibration {
  ProbeCalibration calibration;
  NWireCorrespondence correspondence;
  std::size_t frames_segmented = 0;
  std::size_t frames_total = 0;
  /// How far the image could lie elsewhere: over calibrations of the frames drawn again with
  /// replacement (a bootstrap, fixed seed), the RMS of each one's largest displacement of the
  /// image's corners and centre from this calibration's (1 sigma, metres).
  double uncertainty_m = 0.0;
  std::size_t bootstrap_fits = 0;
};

/// Calibrates from a recording of the phantom. Errors: the phantom is found in fewer than
/// `min_frames` frames, or the fit fails.
Result<NWireCalibration> nwire_calibration(const std::vector<TrackedImage>& frames, const NWirePhantom& phantom,
                                           std::size_t min_frames = 10,
                                           const NWireSegmentationOptions& segmentation = {});

}  // namespace nav::calibration
