#pragma once
// The AprilTag optical tracker: tag36h11 detection (apriltag library) in grey frames, the
// pose of each tag (apriltag's estimate_tag_pose) and of multi-tag rigid bodies (all their
// corners, Gauss-Newton on the reprojection error). Conventions (dependencies.md): corners
// are reported with pixel centres at integers (apriltag's +0.5 removed); the tag frame has x
// right and y down the printed tag, z into it, corners at (-s/2, s/2), (s/2, s/2),
// (s/2, -s/2), (-s/2, -s/2); poses are camera_from_tag in the OpenCV camera frame. With a lens
// distortion, tags are detected in the frame resampled to the ideal pinhole camera (straight
// edges), their poses found there, and their corners reported as seen (through the lens).
// I/O-thread code (detection allocates).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "nav/calibration/lens_distortion.hpp"
#include "nav/core/error.hpp"
#include "nav/trackers/gray_image.hpp"
#include "nav/trackers/tracker_sample.hpp"

namespace nav::trackers {

/// Pinhole intrinsics, pixel centres at integer coordinates, and the lens distortion
/// (navtool calib camera estimates both).
struct CameraIntrinsics {
  double fx_px = 600.0;
  double fy_px = 600.0;
  double cx_px = 319.5;
  double cy_px = 239.5;
  calibration::LensDistortion distortion{};
};

/// Where the camera sees the camera-frame point `p` (z > 0), distortion included.
Eigen::Vector2d project(const CameraIntrinsics& camera, const Eigen::Vector3d& p);
/// The ideal pinhole pixel of the seen (distorted) pixel `seen_px`.
Eigen::Vector2d undistort_pixel(const CameraIntrinsics& camera, const Eigen::Vector2d& seen_px);

/// One detected tag.
struct TagObservation {
  int id = 0;
  int hamming = 0;
  std::array<Eigen::Vector2d, 4> corners_px;  // integer pixel centres
  Eigen::Isometry3d camera_from_tag = Eigen::Isometry3d::Identity();
};

/// A tag of a rigid body, and where it sits on the body.
struct BodyTag {
  int id = 0;
  Eigen::Isometry3d body_from_tag = Eigen::Isometry3d::Identity();
};

/// A rigid body made of one or more tags of the same size.
struct TagBody {
  std::uint32_t tool_id = 0;
  std::vector<BodyTag> tags;
};

/// The tag-frame corner k (apriltag's order) of a tag of edge `tag_size_m`.
Eigen::Vector3d tag_corner(int k, double tag_size_m);

/// Detects tags and tracks rigid bodies in grey frames.
class AprilTagTracker {
 public:
  /// A tracker for tags of edge `tag_size_m` (the black square) seen by `camera`.
  static Result<std::unique_ptr<AprilTagTracker>> create(const CameraIntrinsics& camera, double tag_size_m,
                                                         std::vector<TagBody> bodies);
  ~AprilTagTracker();
  AprilTagTracker(const AprilTagTracker&) = delete;
  AprilTagTracker& operator=(const AprilTagTracker&) = delete;

  /// Every tag36h11 tag in `image`, with its pose.
  std::vector<TagObservation> detect(const GrayImage& image) const;
  /// One sample per body (camera_from_body; missing when none of its tags is seen), measured
  /// at `time_ns`.
  std::vector<TrackerSample> track(const GrayImage& image, TimeNs time_ns) const;
  /// The body pose from the observations of its tags, or nullopt-like false when unseen;
  /// `rms_px` receives the reprojection RMS.
  bool body_pose(const TagBody& body, const std::vector<TagObservation>& observations,
                 Eigen::Isometry3d& camera_from_body, double& rms_px) const;

 private:
  struct Detector;
  AprilTagTracker(const CameraIntrinsics& camera, double tag_size_m, std::vector<TagBody> bodies,
                  std::unique_ptr<Detector> detector);
  CameraIntrinsics camera_;
  double tag_size_m_;
  std::vector<TagBody> bodies_;
  std::unique_ptr<Detector> detector_;
};

/// Renders tag36h11 tags seen by a pinhole camera with its lens distortion, anti-aliased
/// (4x supersampling), with a light blur and seeded Gaussian noise: the synthetic frames of
/// the tracker's tests and of the camera calibration's. Background grey 150.
struct TagRendering {
  int id = 0;
  Eigen::Isometry3d camera_from_tag = Eigen::Isometry3d::Identity();
};
GrayImage render_tags(const std::vector<TagRendering>& tags, double tag_size_m, const CameraIntrinsics& camera,
                      int width_px, int height_px, double noise_grey, std::uint64_t seed);

}  // namespace nav::trackers
