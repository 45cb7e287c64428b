#pragma once
// Valid samples of every station topic, and a wait helper, for the DDS tests.
#include <chrono>
#include <cstring>
#include <memory>
#include <thread>

#include "nav/dds/network_config.hpp"
#include "nav/dds/samples.hpp"

namespace nav::dds::testing {

/// A loopback-only network config on `domain_id` (each test case uses its own domain).
inline NetworkConfig local_network(std::uint32_t domain_id) {
  NetworkConfig config;
  config.domain_id = domain_id;
  config.participant_name = "nav_test";
  return config;
}

inline void set_name(FrameName& name, const char* text) {
  name.fill('\0');
  std::strncpy(name.data(), text, kMaxFrameNameChars);
}

/// A valid pose of `tool_id` at `source_time_ns`: a rotation of 90 degrees about z.
inline ToolPose make_pose(std::uint32_t tool_id, TimeNs source_time_ns) {
  ToolPose pose;
  pose.tool_id = tool_id;
  pose.sequence_number = static_cast<std::uint64_t>(source_time_ns);
  pose.source_time_ns = source_time_ns;
  pose.position_m = {0.10, -0.02, 0.30};
  pose.orientation_wxyz = {0.7071067811865476, 0.0, 0.0, 0.7071067811865476};
  pose.position_covariance_m2 = {1e-8, 0, 0, 0, 1e-8, 0, 0, 0, 1e-8};
  pose.quality = 0.9f;
  set_name(pose.frame_to, "tracker");
  set_name(pose.frame_from, "needle");
  return pose;
}

/// A valid frame of width x height with a gradient image (heap: it is 1 MiB).
inline std::unique_ptr<UltrasoundFrame> make_frame(std::uint32_t width_px, std::uint32_t height_px,
                                                   TimeNs source_time_ns) {
  auto frame = std::make_unique<UltrasoundFrame>();
  frame->sequence_number = 7;
  frame->source_time_ns = source_time_ns;
  frame->probe_tool_id = 2;
  frame->width_px = width_px;
  frame->height_px = height_px;
  frame->pixel_spacing_m = {2e-4, 2e-4};
  frame->depth_m = 0.12;
  for (std::size_t i = 0; i < frame->pixel_count(); ++i)
    frame->pixels[i] = static_cast<std::uint8_t>(i * 7 + i / width_px);
  return frame;
}

/// A valid needle state with `point_count` points along x.
inline NeedleState make_needle(std::uint32_t point_count, TimeNs source_time_ns) {
  NeedleState needle;
  needle.source_time_ns = source_time_ns;
  needle.tool_id = 1;
  needle.point_count = point_count;
  for (std::uint32_t i = 0; i < point_count; ++i) needle.shape_points_m[i] = {0.001 * i, 0.0002 * i * i, -0.01};
  needle.tip_force_n = {0.1, -0.2, 0.5};
  return needle;
}

inline TargetPrediction make_prediction(TimeNs source_time_ns) {
  TargetPrediction prediction;
  prediction.source_time_ns = source_time_ns;
  prediction.horizon_ns = 50 * kNsPerMs;
  prediction.target_id = 3;
  prediction.model_rung = 2;
  prediction.position_m = {0.05, 0.06, 0.07};
  prediction.covariance_m2 = {4e-6, 0, 0, 0, 4e-6, 0, 0, 0, 9e-6};
  return prediction;
}

/// A surface of `vertex_count` vertices (heap: up to 196 KiB).
inline std::unique_ptr<DeformedSurface> make_surface(std::uint32_t vertex_count, TimeNs source_time_ns) {
  auto surface = std::make_unique<DeformedSurface>();
  surface->source_time_ns = source_time_ns;
  surface->surface_id = 4;
  surface->vertex_count = vertex_count;
  for (std::uint32_t i = 0; i < vertex_count; ++i) {
    surface->vertex_positions_m[i] = {0.001f * static_cast<float>(i), 0.5f, -0.25f};
  }
  return surface;
}

inline StationHealth make_health(TimeNs source_time_ns) {
  StationHealth health;
  health.source_time_ns = source_time_ns;
  health.mode = StationMode::running;
  health.flags = 0;
  health.step_time_mean_ns = 150'000;
  health.step_time_max_ns = 420'000;
  health.deadline_misses = 1;
  health.input_age_ns = {3 * kNsPerMs, 250 * kNsPerMs, StationHealth::kNoSampleYet, 40 * kNsPerMs};
  return health;
}

inline NeedleForce make_needle_force(TimeNs source_time_ns) {
  NeedleForce force;
  force.source_time_ns = source_time_ns;
  force.tool_id = 12;
  force.flags = 0;
  force.tip_force_n = {0.1, -0.2, 0.55};
  force.holder_force_n = {-0.05, 0.1, -0.6};
  return force;
}

inline GroundTruth make_truth(TimeNs source_time_ns) {
  GroundTruth truth;
  truth.source_time_ns = source_time_ns;
  truth.tumour_m = {-0.04, -0.005, 0.003};
  truth.needle_tip_m = {-0.04, 0.05, 0.02};
  return truth;
}

/// Polls `done` every millisecond for up to `timeout`; true once it holds.
template <typename Predicate>
bool wait_until(Predicate done, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace nav::dds::testing
