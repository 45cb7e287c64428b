#pragma once
// The plain samples the station exchanges over DDS, as the core and the apps see them:
// fixed-capacity structs with no heap storage and no Fast DDS type, so that they can sit in
// preallocated lock-free buffers. Units are SI; timestamps are monotonic nanoseconds.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "nav/core/clock.hpp"

namespace nav::dds {

inline constexpr std::size_t kMaxFrameNameChars = 31;
inline constexpr std::size_t kMaxFramePixels = std::size_t{1} << 20;  // 1 MiB of 8-bit pixels
inline constexpr std::size_t kMaxNeedlePoints = 128;
inline constexpr std::size_t kMaxSurfaceVertices = 16384;

/// A NUL-terminated frame name of at most kMaxFrameNameChars characters.
using FrameName = std::array<char, kMaxFrameNameChars + 1>;

/// Writes `name` into `out`: NUL-padded, cut at kMaxFrameNameChars characters.
inline void set_frame_name(FrameName& out, std::string_view name) noexcept {
  out.fill('\0');
  std::copy_n(name.begin(), std::min(name.size(), kMaxFrameNameChars), out.begin());
}

/// A point or vector in metres (or newtons, for forces), x y z.
using Vector3 = std::array<double, 3>;
/// A row-major 3x3 covariance.
using Covariance3 = std::array<double, 9>;

/// A tracked tool's pose: the rigid transform T_<frame_to>_<frame_from> at source_time_ns.
struct ToolPose {
  std::uint32_t tool_id = 0;
  std::uint64_t sequence_number = 0;
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;  // set by the receiving listener
  Vector3 position_m{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};  // unit quaternion
  Covariance3 position_covariance_m2{};
  float quality = 0.0f;  // tracker quality, 0 (bad) to 1
  FrameName frame_to{};
  FrameName frame_from{};
};

/// One 8-bit B-mode ultrasound image, row-major, width_px * height_px pixels used.
struct UltrasoundFrame {
  std::uint64_t sequence_number = 0;
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  std::uint32_t probe_tool_id = 0;
  std::uint32_t width_px = 0;
  std::uint32_t height_px = 0;
  std::array<double, 2> pixel_spacing_m{};  // along a row (x), along a column (y)
  double depth_m = 0.0;
  std::array<std::uint8_t, kMaxFramePixels> pixels{};

  std::size_t pixel_count() const noexcept { return std::size_t{width_px} * height_px; }
};

/// The needle's centreline, base first and tip last, and the force on its tip.
struct NeedleState {
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  std::uint32_t tool_id = 0;
  std::uint32_t point_count = 0;
  std::array<Vector3, kMaxNeedlePoints> shape_points_m{};
  Vector3 tip_force_n{};
};

/// The forces on the needle at one tick of the loop (1 kHz), for a haptic display or a robot
/// controller: on its tip, and the force its holder feels (model frame, newtons).
struct NeedleForce {
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  std::uint32_t tool_id = 0;
  std::uint32_t flags = 0;  // HealthFlags bits of the needle model at that tick
  Vector3 tip_force_n{};
  Vector3 holder_force_n{};
};

/// Where a model rung expects a target to be horizon_ns after source_time_ns.
struct TargetPrediction {
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  TimeNs horizon_ns = 0;
  std::uint32_t target_id = 0;
  std::uint32_t model_rung = 0;
  Vector3 position_m{};
  Covariance3 covariance_m2{};
};

/// The deformed organ surface: vertex positions of a topology both sides know by surface_id.
struct DeformedSurface {
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  std::uint32_t surface_id = 0;
  std::uint32_t vertex_count = 0;
  std::array<std::array<float, 3>, kMaxSurfaceVertices> vertex_positions_m{};
};

/// What a simulated patient knows and a station never reads: where the tumour and the needle's
/// tip truly are at source_time_ns (model frame), for evaluating the station from outside.
struct GroundTruth {
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  Vector3 tumour_m{};
  Vector3 needle_tip_m{};
};

/// Samples dropped at the DDS boundary, by reason, and those accepted.
struct BoundaryCounts {
  std::uint64_t accepted = 0;
  std::uint64_t malformed = 0;
  std::uint64_t wrong_size = 0;
  std::uint64_t non_finite = 0;
  std::uint64_t non_unit_quaternion = 0;
  std::uint64_t time_backwards = 0;
  std::uint64_t time_out_of_window = 0;
  std::uint64_t unknown_tool = 0;
  std::uint64_t implausible_pose = 0;
  std::uint64_t buffer_full = 0;
};

/// The station's inputs, each with its own health: the tracked needle, probe and respiratory
/// marker (tool poses) and the ultrasound (frames).
enum class StationInput : std::uint32_t { needle = 0, probe = 1, respiratory = 2, ultrasound = 3 };
inline constexpr std::size_t kStationInputCount = 4;

/// One count or flag set per StationInput, in its order.
template <typename Value>
using PerInput = std::array<Value, kStationInputCount>;

/// What the station is doing, as published in its health.
enum class StationMode : std::uint32_t { starting = 0, running = 1, degraded = 2, stopped = 3 };

/// The station's state and real-time statistics, with the boundary's drop counters.
struct StationHealth {
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  StationMode mode = StationMode::starting;
  std::uint32_t flags = 0;  // HealthFlags bits
  TimeNs step_time_mean_ns = 0;
  TimeNs step_time_max_ns = 0;
  std::uint64_t deadline_misses = 0;
  BoundaryCounts boundary{};
  PerInput<std::uint32_t> input_flags{};    // HealthFlags bits of each input (bad_sample: refused within the hold)
  PerInput<std::uint64_t> input_refused{};  // each input's samples refused at the boundary so far
  /// How old each input's newest good sample was at source_time_ns; kNoSampleYet: none yet.
  PerInput<TimeNs> input_age_ns{kNoSampleYet, kNoSampleYet, kNoSampleYet, kNoSampleYet};
  /// Writers the station's pose and frame readers have matched: a device knows from them that
  /// the station reads it (a sample written before is lost).
  std::uint32_t pose_writers = 0;
  std::uint32_t frame_writers = 0;

  static constexpr TimeNs kNoSampleYet = -1;
};

}  // namespace nav::dds
