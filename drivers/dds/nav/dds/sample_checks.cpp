#include "nav/dds/sample_checks.hpp"

#include <cmath>

namespace nav::dds {
namespace {

template <typename Array>
bool all_finite(const Array& values) noexcept {
  for (const auto value : values) {
    if (!std::isfinite(value)) return false;
  }
  return true;
}

}  // namespace

SampleFault check_sample(const ToolPose& pose) noexcept {
  if (!all_finite(pose.position_m) || !all_finite(pose.orientation_wxyz) || !all_finite(pose.position_covariance_m2) ||
      !std::isfinite(pose.quality)) {
    return SampleFault::non_finite;
  }
  double norm_squared = 0.0;
  for (const double q : pose.orientation_wxyz) norm_squared += q * q;
  if (std::abs(std::sqrt(norm_squared) - 1.0) > kQuaternionNormTolerance) return SampleFault::non_unit_quaternion;
  return SampleFault::none;
}

SampleFault check_sample(const UltrasoundFrame& frame) noexcept {
  if (!all_finite(frame.pixel_spacing_m) || !std::isfinite(frame.depth_m)) return SampleFault::non_finite;
  if (frame.pixel_count() == 0 || frame.pixel_count() > kMaxFramePixels) return SampleFault::wrong_size;
  if (frame.pixel_spacing_m[0] <= 0.0 || frame.pixel_spacing_m[1] <= 0.0 || frame.depth_m <= 0.0) {
    return SampleFault::wrong_size;
  }
  return SampleFault::none;
}

SampleFault check_sample(const NeedleState& needle) noexcept {
  if (needle.point_count > kMaxNeedlePoints) return SampleFault::wrong_size;
  for (std::uint32_t i = 0; i < needle.point_count; ++i) {
    if (!all_finite(needle.shape_points_m[i])) return SampleFault::non_finite;
  }
  return all_finite(needle.tip_force_n) ? SampleFault::none : SampleFault::non_finite;
}

SampleFault check_sample(const TargetPrediction& prediction) noexcept {
  if (!all_finite(prediction.position_m) || !all_finite(prediction.covariance_m2)) return SampleFault::non_finite;
  return SampleFault::none;
}

SampleFault check_sample(const DeformedSurface& surface) noexcept {
  if (surface.vertex_count > kMaxSurfaceVertices) return SampleFault::wrong_size;
  for (std::uint32_t i = 0; i < surface.vertex_count; ++i) {
    if (!all_finite(surface.vertex_positions_m[i])) return SampleFault::non_finite;
  }
  return SampleFault::none;
}

SampleFault check_sample(const StationHealth&) noexcept { return SampleFault::none; }

SampleFault check_sample(const GroundTruth& truth) noexcept {
  return all_finite(truth.tumour_m) && all_finite(truth.needle_tip_m) ? SampleFault::none : SampleFault::non_finite;
}

SampleFault check_sample(const NeedleForce& force) noexcept {
  return all_finite(force.tip_force_n) && all_finite(force.holder_force_n) ? SampleFault::none
                                                                           : SampleFault::non_finite;
}

SampleFault PoseBounds::check(const ToolPose& pose, const ToolPose* previous) const noexcept {
  const auto& p = pose.position_m;
  if (std::hypot(p[0], p[1], p[2]) > volume_radius_m) return SampleFault::implausible_pose;
  if (previous == nullptr) return SampleFault::none;
  const double elapsed_s =
      1e-9 * (static_cast<double>(pose.source_time_ns) - static_cast<double>(previous->source_time_ns));
  if (elapsed_s < 0.0) return SampleFault::none;
  const auto& q = previous->position_m;
  const double moved_m = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
  return moved_m > max_speed_m_per_s * elapsed_s + jitter_m ? SampleFault::implausible_pose : SampleFault::none;
}

}  // namespace nav::dds
