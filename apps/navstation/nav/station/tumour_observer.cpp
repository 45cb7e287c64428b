#include "nav/station/tumour_observer.hpp"

#include <chrono>
#include <cmath>

#include "nav/calibration/frame_tree.hpp"

namespace nav::station {

Result<ProbeImaging> scene_probe_imaging(const Scene& scene) {
  auto frames = calibration::FrameTree::load(scene.frames.urdf_path);
  if (!frames.ok()) return Error{frames.error().describe(), scene.source_path, scene.frames.line, "frames.urdf"};
  auto image_to_probe = frames.value().lookup("probe_marker", "image_plane", 0);
  if (!image_to_probe.ok())
    return Error{"no fixed chain from probe_marker to image_plane: " + image_to_probe.error().describe(), scene.source_path, scene.frames.line,
                 "frames.urdf"};
  ProbeImaging imaging;
  imaging.image_to_probe = image_to_probe.value();
  return imaging;
}

TumourObserver::TumourObserver(const ProbeImaging& imaging, const TumourObserverOptions& options)
    : imaging_(imaging), options_(options) {
  poses_.reserve(options_.pose_history);
}

void TumourObserver::add_probe_pose(TimeNs time_ns, const RigidPose& probe_in_model) {
  if (poses_.size() < options_.pose_history) {
    poses_.push_back({time_ns, probe_in_model});
    return;
  }
  poses_[next_] = {time_ns, probe_in_model};
  next_ = (next_ + 1) % poses_.size();
}

std::optional<RigidPose> TumourObserver::probe_pose_at(TimeNs time_ns) const {
  const std::size_t n = poses_.size();
  const TimedPose* before = nullptr;
  const TimedPose* after = nullptr;
  for (std::size_t k = 0; k < n; ++k) {  // oldest to newest
    const TimedPose& p = poses_[(next_ + k) % n];
    if (p.time_ns <= time_ns) before = &p;
    if (p.time_ns >= time_ns && after == nullptr) after = &p;
  }
  if (before != nullptr && after != nullptr) {
    if (after->time_ns - before->time_ns > options_.max_pose_gap_ns) return std::nullopt;
    if (after->time_ns == before->time_ns) return before->pose;
    const double f = static_cast<double>(time_ns - before->time_ns) / static_cast<double>(after->time_ns - before->time_ns);
    return geodesic(before->pose, after->pose, f);
  }
  if (before != nullptr && time_ns - before->time_ns <= options_.max_pose_gap_ns) return before->pose;
  return std::nullopt;
}

std::optional<Eigen::Vector3d> TumourObserver::observe(TimeNs capture_ns, const std::uint8_t* pixels, std::uint32_t width_px,
                                                       std::uint32_t height_px, double spacing_x_m, double spacing_y_m) {
  ++counts_.frames;
  const auto start = std::chrono::steady_clock::now();
  const ultrasound::TumourDetection found = tracker_.update(pixels, width_px, height_px);
  processing_us_.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
  if (!found.found || found.confidence < options_.min_confidence) {
    ++counts_.dropped_no_detection;
    return std::nullopt;
  }
  const std::optional<RigidPose> probe = probe_pose_at(capture_ns);
  if (!probe) {
    ++counts_.dropped_no_pose;
    return std::nullopt;
  }
  Eigen::Isometry3d probe_to_model = Eigen::Isometry3d::Identity();
  probe_to_model.linear() = probe->rotation.toRotationMatrix();
  probe_to_model.translation() = probe->position_m;
  ++counts_.observations;
  return ultrasound::image_point_in_world(found.u_px, found.v_px, spacing_x_m, spacing_y_m, imaging_.image_to_probe, probe_to_model);
}

}  // namespace nav::station
