#pragma once
// The station's rigid frames, described by a URDF (urdfdom): links are frames (tracker,
// reference marker, needle marker, needle base, needle tip, probe marker, image plane,
// camera), fixed joints are calibrated transforms, floating joints are tracked tool poses
// fed with timestamps. Looks up the transform between any two frames at a time, SLERP
// between tracked samples, and writes calibration results back as joint origins with their
// date and residual (attributes nav_calibrated and nav_residual_m on <origin>).
// Init-time and I/O-side code: it allocates.
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// A calibration's record on a joint: when and how well it was measured.
struct CalibrationRecord {
  std::string date;         // ISO 8601, UTC
  double residual_m = 0.0;  // RMS residual of the calibration
};

/// One joint of the tree: parent frame, child frame and, for fixed joints, parent_from_child.
struct FrameJoint {
  std::string name;
  std::string parent;
  std::string child;
  bool tracked = false;  // a floating joint, fed by add_pose()
  Transform parent_from_child = Transform::Identity();
  std::optional<CalibrationRecord> record;  // set when a calibration wrote this joint
};

/// The frame tree of one station.
class FrameTree {
 public:
  /// Parses the URDF file at `path`; errors name the file, line and element.
  static Result<FrameTree> load(const std::string& path);
  /// Parses URDF text; `path` only names it in errors.
  static Result<FrameTree> parse(const std::string& xml, const std::string& path);

  /// Every frame (link) name, sorted.
  std::vector<std::string> frames() const;
  /// The joint called `name`, or null.
  const FrameJoint* joint(const std::string& name) const;

  /// Buffers a tracked pose parent_from_child of the floating joint whose child is `frame`, at
  /// `time_ns` (strictly after the previous one). Keeps the newest `kPoseHistory` samples.
  Status add_pose(const std::string& frame, TimeNs time_ns, const Transform& parent_from_child);
  /// target_from_source at `time_ns`: maps points of `source` into `target`. Tracked joints on
  /// the path are interpolated; a time outside a joint's buffered span is an error.
  Result<Transform> lookup(const std::string& target, const std::string& source, TimeNs time_ns) const;

  /// Sets the origin of the fixed joint `joint_name` to `parent_from_child` with its record.
  Status set_calibration(const std::string& joint_name, const Transform& parent_from_child,
                         const CalibrationRecord& record);
  /// Writes the URDF, with every calibrated origin, to `path`.
  Status save(const std::string& path) const;

  static constexpr std::size_t kPoseHistory = 4096;

 private:
  struct TimedPose {
    TimeNs time_ns;
    Transform parent_from_child;
  };
  Result<Transform> joint_transform(const FrameJoint& joint, TimeNs time_ns) const;
  /// The frames from `frame` up to the root (both included); empty for an unknown frame.
  std::vector<std::string> path_to_root(const std::string& frame) const;
  /// ancestor_from_frame for path[0] = frame and path[ancestor_index] = ancestor.
  Result<Transform> ancestor_from_frame(const std::vector<std::string>& path, std::size_t ancestor_index,
                                        TimeNs time_ns) const;

  std::string source_path_;
  std::string xml_;  // the document as loaded, rewritten by save()
  std::string root_;
  std::map<std::string, FrameJoint> joints_;              // by joint name
  std::map<std::string, std::string> joint_of_child_;     // child frame -> joint name
  std::map<std::string, std::deque<TimedPose>> history_;  // child frame -> tracked poses
};

/// Today's date and time in UTC as ISO 8601 ("2026-11-21T12:00:00Z").
std::string utc_timestamp();

}  // namespace nav::calibration
