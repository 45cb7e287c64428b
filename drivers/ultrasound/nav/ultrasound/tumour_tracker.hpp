#pragma once
// Finds and tracks a hypoechoic (dark, round) tumour in B-mode frames (OpenCV imgproc), and
// turns its centre into a 3-D point through the probe calibration and the probe's pose.
// Runs on the image-processing thread, not in the real-time step: OpenCV allocates.
#include <Eigen/Geometry>
#include <cstdint>

namespace nav::ultrasound {

/// What the tracker looks for: the tumour's cross-section radius range (pixels), how far it
/// may move between frames, and how dark it is against the surrounding tissue.
struct TumourTrackerOptions {
  double min_radius_px = 8.0;
  double max_radius_px = 120.0;
  double max_step_px = 40.0;        ///< beyond this from the last detection, a blob is a new target
  double dark_fraction = 0.5;       ///< dark: smoothed intensity below this fraction of the median
  double smoothing_sigma_px = 4.0;  ///< speckle reduction before thresholding
};

/// One frame's result: the centre and equivalent radius of the dark region (pixels), and a
/// confidence in [0, 1] (contrast against the surroundings times roundness).
struct TumourDetection {
  bool found = false;
  double u_px = 0.0;
  double v_px = 0.0;
  double radius_px = 0.0;
  double confidence = 0.0;
};

/// Detects the tumour frame after frame, preferring the region nearest the last detection.
class TumourTracker {
 public:
  /// Image processing runs on the station's I/O thread alone: OpenCV's worker threads would
  /// compete with the real-time core, so a tracker switches OpenCV's parallel loops off
  /// (process-wide).
  explicit TumourTracker(const TumourTrackerOptions& options = {});

  /// Looks for the tumour in an 8-bit row-major frame.
  TumourDetection update(const std::uint8_t* pixels, std::uint32_t width_px, std::uint32_t height_px);
  /// Forgets the last detection (the next frame searches the whole image).
  void reset() noexcept { last_ = {}; }

 private:
  TumourTrackerOptions options_;
  TumourDetection last_;
};

/// A pixel (u, v) as a point of the world (metres): probe_from_image (the probe calibration)
/// maps the image point (u * spacing_x, v * spacing_y, 0) to the probe frame, and
/// world_from_probe (the tracked pose) the probe frame to the world.
Eigen::Vector3d image_point_in_world(double u_px, double v_px, double spacing_x_m, double spacing_y_m,
                                     const Eigen::Isometry3d& probe_from_image,
                                     const Eigen::Isometry3d& world_from_probe);

}  // namespace nav::ultrasound
