#pragma once
// The station's ultrasound image processing (I/O thread): finds the tumour in each B-mode
// frame with the TumourTracker and turns its centre into a point of the model frame through
// the probe calibration (image frame to probe marker) and the tracked probe pose at the
// frame's capture time (interpolated between the tracker's samples, SLERP). Frames without
// a confident detection, or without probe poses around their capture time, are dropped and
// counted. Not real-time code: OpenCV allocates.
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/fusion/rigid_pose.hpp"
#include "nav/station/scene.hpp"
#include "nav/ultrasound/bmode_simulator.hpp"
#include "nav/ultrasound/tumour_tracker.hpp"

namespace nav::station {

/// The tracked probe's imaging: the image grid and the probe calibration probe_from_image.
struct ProbeImaging {
  ultrasound::BmodeGeometry geometry;
  Eigen::Isometry3d probe_from_image = Eigen::Isometry3d::Identity();
};

/// The probe of `scene`: its calibration probe_from_image is the URDF's chain from probe_marker to
/// image_plane (`navtool calib probe` writes it); its grid, the simulated scanner's (a station
/// reads each frame on the frame's own grid). Errors name the scene file and frames.urdf.
Result<ProbeImaging> scene_probe_imaging(const Scene& scene);

/// How the observer decides.
struct TumourObserverOptions {
  double min_confidence = 0.5;              ///< detections below it are dropped
  TimeNs max_pose_gap_ns = 100 * kNsPerMs;  ///< probe poses further from the capture time do not place a frame
  std::size_t pose_history = 64;            ///< probe poses kept (about 1 s at 60 Hz)
};

/// What the observer did with the frames it was given.
struct ObserverCounts {
  std::int64_t frames = 0;
  std::int64_t observations = 0;
  std::int64_t dropped_no_detection = 0;  ///< no tumour found, or below min_confidence
  std::int64_t dropped_no_pose = 0;       ///< no probe pose around the capture time
};

/// Frame in, tumour point (model frame) out. One thread.
class TumourObserver {
 public:
  TumourObserver(const ProbeImaging& imaging, const TumourObserverOptions& options = {});

  /// A tracked probe pose (model_from_probe) measured at `time_ns`; poses come in time order.
  void add_probe_pose(TimeNs time_ns, const RigidPose& model_from_probe);

  /// The tumour of an 8-bit row-major frame captured at `capture_ns`, or nothing (counted).
  std::optional<Eigen::Vector3d> observe(TimeNs capture_ns, const std::uint8_t* pixels, std::uint32_t width_px,
                                         std::uint32_t height_px, double spacing_x_m, double spacing_y_m);

  const ObserverCounts& counts() const noexcept { return counts_; }
  /// The wall time observe() took, one entry per frame (microseconds).
  const std::vector<double>& processing_us() const noexcept { return processing_us_; }

 private:
  /// The probe pose at `time_ns`, interpolated (or held within max_pose_gap_ns of the newest).
  std::optional<RigidPose> probe_pose_at(TimeNs time_ns) const;

  ProbeImaging imaging_;
  TumourObserverOptions options_;
  ultrasound::TumourTracker tracker_;
  std::vector<TimedPose> poses_;  ///< a ring of pose_history entries, oldest at next_
  std::size_t next_ = 0;
  ObserverCounts counts_;
  std::vector<double> processing_us_;
};

}  // namespace nav::station
