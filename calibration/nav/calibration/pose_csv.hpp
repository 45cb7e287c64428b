#pragma once
// The calibration commands' recorded-pose and point files: plain CSV, one record a line,
// '#' comments and blank lines ignored, lengths in metres.
//   poses:  time_s,tool,x_m,y_m,z_m,qw,qx,qy,qz   (tracker_from_tool; tool is a name or id)
//   points: x_m,y_m,z_m
#include <string>
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// One recorded pose of a tool.
struct RecordedPose {
  TimeNs time_ns = 0;
  std::string tool;
  Transform pose = Transform::Identity();
};

/// Reads a pose CSV; errors name the file, line and column. Quaternions must be unit (1e-3).
Result<std::vector<RecordedPose>> read_pose_csv(const std::string& path);
/// Reads a point CSV; errors name the file, line and column.
Result<std::vector<Eigen::Vector3d>> read_point_csv(const std::string& path);
/// The poses of `tool` (all poses when `tool` is empty).
std::vector<Transform> poses_of(const std::vector<RecordedPose>& poses, const std::string& tool);

/// Writes poses in the format read_pose_csv reads (for recordings of the simulated devices).
Status write_pose_csv(const std::string& path, const std::vector<RecordedPose>& poses);

}  // namespace nav::calibration
