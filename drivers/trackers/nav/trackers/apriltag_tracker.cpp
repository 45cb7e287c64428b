#include "nav/trackers/apriltag_tracker.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/apriltag_pose.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/tag36h11.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace nav::trackers {
namespace {

/// exp of a small twist (rotation vector, translation) applied on the left of `pose`.
Eigen::Isometry3d nudge(const Eigen::Isometry3d& pose, const Eigen::Matrix<double, 6, 1>& twist) {
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d rotation = twist.head<3>();
  if (rotation.norm() > 0.0)
    delta.linear() = Eigen::AngleAxisd(rotation.norm(), rotation.normalized()).toRotationMatrix();
  delta.translation() = twist.tail<3>();
  return delta * pose;
}

/// The ray (z = 1) of the ideal pinhole pixel (u, v).
Eigen::Vector3d pinhole_ray(const CameraIntrinsics& camera, double u_px, double v_px) {
  return {(u_px - camera.cx_px) / camera.fx_px, (v_px - camera.cy_px) / camera.fy_px, 1.0};
}

}  // namespace

Eigen::Vector2d project(const CameraIntrinsics& camera, const Eigen::Vector3d& p) {
  const Eigen::Vector2d seen = calibration::distort(camera.distortion, Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()));
  return {camera.fx_px * seen.x() + camera.cx_px, camera.fy_px * seen.y() + camera.cy_px};
}

Eigen::Vector2d undistort_pixel(const CameraIntrinsics& camera, const Eigen::Vector2d& seen_px) {
  const Eigen::Vector2d ideal = calibration::undistort(
      camera.distortion,
      Eigen::Vector2d((seen_px.x() - camera.cx_px) / camera.fx_px, (seen_px.y() - camera.cy_px) / camera.fy_px));
  return {camera.fx_px * ideal.x() + camera.cx_px, camera.fy_px * ideal.y() + camera.cy_px};
}

struct AprilTagTracker::Detector {
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;
  cv::Mat seen_from_ideal;  ///< per ideal pinhole pixel, where the lens shows it (CV_32FC2)
  cv::Mat rectified;
  ~Detector() {
    if (detector != nullptr) apriltag_detector_destroy(detector);
    if (family != nullptr) tag36h11_destroy(family);
  }
};

Eigen::Vector3d tag_corner(int k, double tag_size_m) {
  static constexpr double kSigns[4][2] = {{-1.0, 1.0}, {1.0, 1.0}, {1.0, -1.0}, {-1.0, -1.0}};
  return {kSigns[k][0] * tag_size_m / 2.0, kSigns[k][1] * tag_size_m / 2.0, 0.0};
}

AprilTagTracker::AprilTagTracker(const CameraIntrinsics& camera, double tag_size_m, std::vector<TagBody> bodies,
                                 std::unique_ptr<Detector> detector)
    : camera_(camera), tag_size_m_(tag_size_m), bodies_(std::move(bodies)), detector_(std::move(detector)) {}

AprilTagTracker::~AprilTagTracker() = default;

Result<std::unique_ptr<AprilTagTracker>> AprilTagTracker::create(const CameraIntrinsics& camera, double tag_size_m,
                                                                 std::vector<TagBody> bodies) {
  if (!(tag_size_m > 0.0)) return Error{.message = "tag size must be positive", .field = "tag_size_m"};
  if (!(camera.fx_px > 0.0 && camera.fy_px > 0.0))
    return Error{.message = "focal lengths must be positive", .field = "camera"};
  for (const TagBody& body : bodies) {
    if (body.tags.empty())
      return Error{.message = "a rigid body needs at least one tag", .field = "tool " + std::to_string(body.tool_id)};
  }
  auto detector = std::make_unique<Detector>();
  detector->family = tag36h11_create();
  detector->detector = apriltag_detector_create();
  apriltag_detector_add_family(detector->detector, detector->family);
  detector->detector->quad_decimate = 1.0f;
  detector->detector->nthreads = 1;
  return std::unique_ptr<AprilTagTracker>(
      new AprilTagTracker(camera, tag_size_m, std::move(bodies), std::move(detector)));
}

std::vector<TagObservation> AprilTagTracker::detect(const GrayImage& image) const {
  image_u8_t wrapped{image.width_px, image.height_px, image.width_px, const_cast<std::uint8_t*>(image.pixels.data())};
  const bool lens = !camera_.distortion.is_zero();
  if (lens) {
    // Detect in the image resampled to the ideal pinhole camera, where the tags' edges are
    // straight again; the map is built once per image size.
    Detector& d = *detector_;
    if (d.seen_from_ideal.rows != image.height_px || d.seen_from_ideal.cols != image.width_px) {
      d.seen_from_ideal.create(image.height_px, image.width_px, CV_32FC2);
      for (int v = 0; v < image.height_px; ++v) {
        for (int u = 0; u < image.width_px; ++u) {
          const Eigen::Vector2d seen = project(camera_, pinhole_ray(camera_, u, v));
          d.seen_from_ideal.at<cv::Vec2f>(v, u) = cv::Vec2f(static_cast<float>(seen.x()), static_cast<float>(seen.y()));
        }
      }
    }
    const cv::Mat raw(image.height_px, image.width_px, CV_8UC1, wrapped.buf);
    cv::remap(raw, d.rectified, d.seen_from_ideal, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    wrapped.buf = d.rectified.data;
  }
  zarray_t* detections = apriltag_detector_detect(detector_->detector, &wrapped);
  std::vector<TagObservation> observations;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* detection = nullptr;
    zarray_get(detections, i, &detection);
    TagObservation observation;
    observation.id = detection->id;
    observation.hamming = detection->hamming;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d corner(detection->p[k][0] - 0.5, detection->p[k][1] - 0.5);
      // Reported as seen: an ideal corner back through the lens.
      observation.corners_px[k] = lens ? project(camera_, pinhole_ray(camera_, corner.x(), corner.y())) : corner;
    }
    // apriltag's pixel centres sit at +0.5: shift the principal point instead of the corners.
    apriltag_detection_info_t info{detection,     tag_size_m_,         camera_.fx_px,
                                   camera_.fy_px, camera_.cx_px + 0.5, camera_.cy_px + 0.5};
    apriltag_pose_t pose{};
    estimate_tag_pose(&info, &pose);
    Eigen::Matrix3d rotation;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) rotation(r, c) = pose.R->data[3 * r + c];
    }
    observation.camera_from_tag.linear() = rotation;
    observation.camera_from_tag.translation() = Eigen::Vector3d(pose.t->data[0], pose.t->data[1], pose.t->data[2]);
    std::free(pose.R);  // matd_destroy is not exported; a matd_t is one calloc block
    std::free(pose.t);
    observations.push_back(observation);
  }
  apriltag_detections_destroy(detections);
  return observations;
}

bool AprilTagTracker::body_pose(const TagBody& body, const std::vector<TagObservation>& observations,
                                Eigen::Isometry3d& camera_from_body, double& rms_px) const {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  const TagObservation* first = nullptr;
  Eigen::Isometry3d first_body_from_tag = Eigen::Isometry3d::Identity();
  for (const BodyTag& tag : body.tags) {
    for (const TagObservation& observation : observations) {
      if (observation.id != tag.id) continue;
      if (first == nullptr) {
        first = &observation;
        first_body_from_tag = tag.body_from_tag;
      }
      for (int k = 0; k < 4; ++k) {
        points.push_back(tag.body_from_tag * tag_corner(k, tag_size_m_));
        pixels.push_back(observation.corners_px[k]);
      }
    }
  }
  if (first == nullptr) return false;
  camera_from_body = first->camera_from_tag * first_body_from_tag.inverse();
  // Gauss-Newton on the reprojection error of every corner (numerical Jacobian).
  const auto residuals = [&](const Eigen::Isometry3d& pose) {
    Eigen::VectorXd r(2 * static_cast<Eigen::Index>(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i) {
      r.segment<2>(2 * static_cast<Eigen::Index>(i)) = project(camera_, pose * points[i]) - pixels[i];
    }
    return r;
  };
  for (int iteration = 0; iteration < 10; ++iteration) {
    const Eigen::VectorXd r0 = residuals(camera_from_body);
    Eigen::MatrixXd jacobian(r0.size(), 6);
    for (int j = 0; j < 6; ++j) {
      Eigen::Matrix<double, 6, 1> step = Eigen::Matrix<double, 6, 1>::Zero();
      step(j) = 1e-7;
      jacobian.col(j) = (residuals(nudge(camera_from_body, step)) - residuals(nudge(camera_from_body, -step))) / 2e-7;
    }
    const Eigen::Matrix<double, 6, 1> update =
        (jacobian.transpose() * jacobian).ldlt().solve(-jacobian.transpose() * r0);
    camera_from_body = nudge(camera_from_body, update);
    if (update.norm() < 1e-12) break;
  }
  rms_px = std::sqrt(residuals(camera_from_body).squaredNorm() / static_cast<double>(points.size()));
  return true;
}

std::vector<TrackerSample> AprilTagTracker::track(const GrayImage& image, TimeNs time_ns) const {
  const std::vector<TagObservation> observations = detect(image);
  std::vector<TrackerSample> samples;
  for (const TagBody& body : bodies_) {
    TrackerSample sample;
    sample.tool_id = body.tool_id;
    sample.measured_time_ns = time_ns;
    Eigen::Isometry3d pose;
    double rms_px = 0.0;
    if (body_pose(body, observations, pose, rms_px)) {
      sample.state = ToolState::ok;
      const Eigen::Quaterniond q(pose.rotation());
      sample.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
      sample.position_m = {pose.translation().x(), pose.translation().y(), pose.translation().z()};
      // The reprojection RMS as a distance at the body's depth.
      sample.rms_error_m = rms_px * pose.translation().z() / camera_.fx_px;
    }
    samples.push_back(sample);
  }
  return samples;
}

}  // namespace nav::trackers
