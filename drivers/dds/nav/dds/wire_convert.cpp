#include "nav/dds/wire_convert.hpp"

#include <algorithm>

namespace nav::dds {

// The IDL and the plain structs state the same bounds.
static_assert(nav_msgs::kMaxFrameNameChars == kMaxFrameNameChars);
static_assert(nav_msgs::kMaxFramePixels == kMaxFramePixels);
static_assert(nav_msgs::kMaxNeedlePoints == kMaxNeedlePoints &&
              nav_msgs::kMaxNeedleCoordinates == 3 * kMaxNeedlePoints);
static_assert(nav_msgs::kMaxSurfaceVertices == kMaxSurfaceVertices &&
              nav_msgs::kMaxSurfaceCoordinates == 3 * kMaxSurfaceVertices);

namespace {

using WireName = eprosima::fastrtps::fixed_string<kMaxFrameNameChars>;

void copy_name(const FrameName& name, WireName& wire) { wire = name.data(); }

void copy_name(const WireName& wire, FrameName& name) noexcept { set_frame_name(name, {wire.c_str(), wire.size()}); }

/// Copies `coordinates` (x y z of each point, flat) into `points`; false when the count is
/// not a multiple of 3 or exceeds `points`.
template <typename Coordinates, typename Points>
bool unflatten(const Coordinates& coordinates, Points& points, std::uint32_t& point_count) noexcept {
  if (coordinates.size() % 3 != 0 || coordinates.size() / 3 > points.size()) return false;
  point_count = static_cast<std::uint32_t>(coordinates.size() / 3);
  for (std::uint32_t i = 0; i < point_count; ++i) {
    for (std::size_t axis = 0; axis < 3; ++axis) points[i][axis] = coordinates[3 * i + axis];
  }
  return true;
}

/// The first `point_count` points of `points`, flat into `coordinates` (no reallocation
/// once `coordinates` has grown to the bound).
template <typename Points, typename Coordinates>
void flatten(const Points& points, std::uint32_t point_count, Coordinates& coordinates) {
  coordinates.resize(std::size_t{3} * std::min<std::size_t>(point_count, points.size()));
  for (std::size_t i = 0; i < coordinates.size(); ++i) coordinates[i] = points[i / 3][i % 3];
}

}  // namespace

void to_wire(const ToolPose& sample, nav_msgs::ToolPose& wire) {
  wire.tool_id(sample.tool_id);
  wire.sequence_number(sample.sequence_number);
  wire.source_time_ns(sample.source_time_ns);
  wire.position_m() = sample.position_m;
  wire.orientation_wxyz() = sample.orientation_wxyz;
  wire.position_covariance_m2() = sample.position_covariance_m2;
  wire.quality(sample.quality);
  copy_name(sample.frame_to, wire.frame_to());
  copy_name(sample.frame_from, wire.frame_from());
}

SampleFault from_wire(const nav_msgs::ToolPose& wire, ToolPose& sample) noexcept {
  sample.tool_id = wire.tool_id();
  sample.sequence_number = wire.sequence_number();
  sample.source_time_ns = wire.source_time_ns();
  sample.position_m = wire.position_m();
  sample.orientation_wxyz = wire.orientation_wxyz();
  sample.position_covariance_m2 = wire.position_covariance_m2();
  sample.quality = wire.quality();
  copy_name(wire.frame_to(), sample.frame_to);
  copy_name(wire.frame_from(), sample.frame_from);
  return SampleFault::none;
}

void to_wire(const UltrasoundFrame& sample, nav_msgs::UltrasoundFrame& wire) {
  wire.sequence_number(sample.sequence_number);
  wire.source_time_ns(sample.source_time_ns);
  wire.probe_tool_id(sample.probe_tool_id);
  wire.width_px(sample.width_px);
  wire.height_px(sample.height_px);
  wire.pixel_spacing_m() = sample.pixel_spacing_m;
  wire.depth_m(sample.depth_m);
  const std::size_t count = std::min(sample.pixel_count(), kMaxFramePixels);
  wire.pixels().assign(sample.pixels.begin(), sample.pixels.begin() + static_cast<std::ptrdiff_t>(count));
}

SampleFault from_wire(const nav_msgs::UltrasoundFrame& wire, UltrasoundFrame& sample) noexcept {
  sample.sequence_number = wire.sequence_number();
  sample.source_time_ns = wire.source_time_ns();
  sample.probe_tool_id = wire.probe_tool_id();
  sample.width_px = wire.width_px();
  sample.height_px = wire.height_px();
  sample.pixel_spacing_m = wire.pixel_spacing_m();
  sample.depth_m = wire.depth_m();
  const std::size_t count = wire.pixels().size();
  if (count != sample.pixel_count() || count > kMaxFramePixels) return SampleFault::wrong_size;
  std::copy(wire.pixels().begin(), wire.pixels().end(), sample.pixels.begin());  // not memcpy: data() may be null
  return SampleFault::none;
}

void to_wire(const NeedleState& sample, nav_msgs::NeedleState& wire) {
  wire.source_time_ns(sample.source_time_ns);
  wire.tool_id(sample.tool_id);
  flatten(sample.shape_points_m, sample.point_count, wire.shape_points_m());
  wire.tip_force_n() = sample.tip_force_n;
}

SampleFault from_wire(const nav_msgs::NeedleState& wire, NeedleState& sample) noexcept {
  sample.source_time_ns = wire.source_time_ns();
  sample.tool_id = wire.tool_id();
  sample.tip_force_n = wire.tip_force_n();
  return unflatten(wire.shape_points_m(), sample.shape_points_m, sample.point_count) ? SampleFault::none
                                                                                     : SampleFault::wrong_size;
}

void to_wire(const TargetPrediction& sample, nav_msgs::TargetPrediction& wire) {
  wire.source_time_ns(sample.source_time_ns);
  wire.horizon_ns(sample.horizon_ns);
  wire.target_id(sample.target_id);
  wire.model_rung(sample.model_rung);
  wire.position_m() = sample.position_m;
  wire.covariance_m2() = sample.covariance_m2;
}

SampleFault from_wire(const nav_msgs::TargetPrediction& wire, TargetPrediction& sample) noexcept {
  sample.source_time_ns = wire.source_time_ns();
  sample.horizon_ns = wire.horizon_ns();
  sample.target_id = wire.target_id();
  sample.model_rung = wire.model_rung();
  sample.position_m = wire.position_m();
  sample.covariance_m2 = wire.covariance_m2();
  return SampleFault::none;
}

void to_wire(const NeedleForce& sample, nav_msgs::NeedleForce& wire) {
  wire.source_time_ns(sample.source_time_ns);
  wire.tool_id(sample.tool_id);
  wire.flags(sample.flags);
  wire.tip_force_n() = sample.tip_force_n;
  wire.holder_force_n() = sample.holder_force_n;
}

SampleFault from_wire(const nav_msgs::NeedleForce& wire, NeedleForce& sample) noexcept {
  sample.source_time_ns = wire.source_time_ns();
  sample.tool_id = wire.tool_id();
  sample.flags = wire.flags();
  sample.tip_force_n = wire.tip_force_n();
  sample.holder_force_n = wire.holder_force_n();
  return SampleFault::none;
}

void to_wire(const GroundTruth& sample, nav_msgs::GroundTruth& wire) {
  wire.source_time_ns(sample.source_time_ns);
  wire.tumour_m() = sample.tumour_m;
  wire.needle_tip_m() = sample.needle_tip_m;
}

SampleFault from_wire(const nav_msgs::GroundTruth& wire, GroundTruth& sample) noexcept {
  sample.source_time_ns = wire.source_time_ns();
  sample.tumour_m = wire.tumour_m();
  sample.needle_tip_m = wire.needle_tip_m();
  return SampleFault::none;
}

void to_wire(const DeformedSurface& sample, nav_msgs::DeformedSurface& wire) {
  wire.source_time_ns(sample.source_time_ns);
  wire.surface_id(sample.surface_id);
  flatten(sample.vertex_positions_m, sample.vertex_count, wire.vertex_positions_m());
}

SampleFault from_wire(const nav_msgs::DeformedSurface& wire, DeformedSurface& sample) noexcept {
  sample.source_time_ns = wire.source_time_ns();
  sample.surface_id = wire.surface_id();
  return unflatten(wire.vertex_positions_m(), sample.vertex_positions_m, sample.vertex_count) ? SampleFault::none
                                                                                              : SampleFault::wrong_size;
}

void to_wire(const StationHealth& sample, nav_msgs::StationHealth& wire) {
  wire.source_time_ns(sample.source_time_ns);
  wire.mode(static_cast<std::uint32_t>(sample.mode));
  wire.flags(sample.flags);
  wire.step_time_mean_ns(sample.step_time_mean_ns);
  wire.step_time_max_ns(sample.step_time_max_ns);
  wire.deadline_misses(sample.deadline_misses);
  wire.accepted_samples(sample.boundary.accepted);
  wire.dropped_malformed(sample.boundary.malformed);
  wire.dropped_wrong_size(sample.boundary.wrong_size);
  wire.dropped_non_finite(sample.boundary.non_finite);
  wire.dropped_non_unit_quaternion(sample.boundary.non_unit_quaternion);
  wire.dropped_time_backwards(sample.boundary.time_backwards);
  wire.dropped_time_out_of_window(sample.boundary.time_out_of_window);
  wire.dropped_unknown_tool(sample.boundary.unknown_tool);
  wire.dropped_implausible_pose(sample.boundary.implausible_pose);
  wire.dropped_buffer_full(sample.boundary.buffer_full);
  for (std::size_t i = 0; i < kStationInputCount; ++i) {
    wire.input_flags()[i] = sample.input_flags[i];
    wire.input_refused()[i] = sample.input_refused[i];
    wire.input_age_ns()[i] = sample.input_age_ns[i];
  }
  wire.pose_writers(sample.pose_writers);
  wire.frame_writers(sample.frame_writers);
}

SampleFault from_wire(const nav_msgs::StationHealth& wire, StationHealth& sample) noexcept {
  if (wire.mode() > static_cast<std::uint32_t>(StationMode::stopped)) return SampleFault::wrong_size;
  sample.source_time_ns = wire.source_time_ns();
  sample.mode = static_cast<StationMode>(wire.mode());
  sample.flags = wire.flags();
  sample.step_time_mean_ns = wire.step_time_mean_ns();
  sample.step_time_max_ns = wire.step_time_max_ns();
  sample.deadline_misses = wire.deadline_misses();
  sample.boundary.accepted = wire.accepted_samples();
  sample.boundary.malformed = wire.dropped_malformed();
  sample.boundary.wrong_size = wire.dropped_wrong_size();
  sample.boundary.non_finite = wire.dropped_non_finite();
  sample.boundary.non_unit_quaternion = wire.dropped_non_unit_quaternion();
  sample.boundary.time_backwards = wire.dropped_time_backwards();
  sample.boundary.time_out_of_window = wire.dropped_time_out_of_window();
  sample.boundary.unknown_tool = wire.dropped_unknown_tool();
  sample.boundary.implausible_pose = wire.dropped_implausible_pose();
  sample.boundary.buffer_full = wire.dropped_buffer_full();
  for (std::size_t i = 0; i < kStationInputCount; ++i) {
    sample.input_flags[i] = wire.input_flags()[i];
    sample.input_refused[i] = wire.input_refused()[i];
    sample.input_age_ns[i] = wire.input_age_ns()[i] < 0 ? StationHealth::kNoSampleYet : wire.input_age_ns()[i];
  }
  sample.pose_writers = wire.pose_writers();
  sample.frame_writers = wire.frame_writers();
  return SampleFault::none;
}

}  // namespace nav::dds
