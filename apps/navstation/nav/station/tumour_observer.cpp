#include "nav/station/tumour_observer.hpp"

#include <chrono>
#include <cmath>

#include "nav/station/scene_frames.hpp"

namespace nav::station {

Result<ProbeImaging> scene_probe_imaging(const Scene& scene) {
  auto probe_from_image = scene_fixed_chain(scene, "probe_marker", "image_plane");
  if (!probe_from_image.ok()) return probe_from_image.error();
  ProbeImaging imaging;
  imaging.probe_from_image = probe_from_image.value();
  return imaging;
}

TumourObserver::TumourObserver(const ProbeImaging& imaging, const TumourObserverOptions& options)
    : imaging_(imaging), options_(options) {
  poses_.reserve(options_.pose_history);
}

void TumourObserver::add_probe_pose(TimeNs time_ns, const RigidPose& model_from_probe) {
  if (poses_.size() < options_.pose_history) {
    poses_.push_back({time_ns, model_from_probe});
    return;
  }
  poses_[next_] = {time_ns, model_from_probe};
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
    const double f =
        static_cast<double>(time_ns - before->time_ns) / static_cast<double>(after->time_ns - before->time_ns);
    return geodesic(before->pose, after->pose, f);
  }
  if (before != nullptr && time_ns - before->time_ns <= options_.max_pose_gap_ns) return before->pose;
  return std::nullopt;
}

std::optional<Eigen::Vector3d> TumourObserver::observe(TimeNs capture_ns, const std::uint8_t* pixels,
                                                       std::uint32_t width_px, std::uint32_t height_px,
                                                       double spacing_x_m, double spacing_y_m) {
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
  Eigen::Isometry3d model_from_probe = Eigen::Isometry3d::Identity();
  model_from_probe.linear() = probe->rotation.toRotationMatrix();
  model_from_probe.translation() = probe->position_m;
  ++counts_.observations;
  return ultrasound::image_point_in_world(found.u_px, found.v_px, spacing_x_m, spacing_y_m, imaging_.probe_from_image,
                                          model_from_probe);
}

}  // namespace nav::station
