#pragma once
// What the `navtool calib ...` commands share: "--name value" options, recorded tool poses
// (CSV or a DDS recording), and writing a result into the station URDF as a joint origin
// with its date and residual.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "nav/calibration/frame_tree.hpp"
#include "nav/calibration/pose_csv.hpp"

namespace navtool {

/// Options "--name value" of a calib command; flags outside `known` are errors.
struct CalibOptions {
  std::map<std::string, std::string> values;

  /// Parses `args`; prints the error and returns nullopt on an unknown or valueless option.
  static std::optional<CalibOptions> parse(const std::vector<std::string>& args, const std::vector<std::string>& known);
  /// The value of `name`, or `fallback`.
  std::string get(const std::string& name, const std::string& fallback = "") const;
  bool has(const std::string& name) const { return values.count(name) != 0; }
};

/// Loads --urdf, sets `joint` to `parent_from_child` with today's date and `residual_m`, and
/// saves to --out (default: over --urdf). Returns the exit code, printing any error.
int write_calibration(const CalibOptions& options, const std::string& joint,
                      const nav::calibration::Transform& parent_from_child, double residual_m);

/// The tool poses (nav/tool_pose samples, T_<frame_to>_<frame_from> as the tracker sent them)
/// of a DDS recording made by `navtool record`, in recorded order, each tool named by its id
/// ("3"). Damaged records are skipped with a note on stderr. Errors: unreadable file, no
/// recording, no pose in it.
nav::Result<std::vector<nav::calibration::RecordedPose>> read_recorded_tool_poses(const std::string& path);

/// The poses of --poses FILE.csv or of --recording FILE.navrec (exactly one of them); the
/// error names the option or the file.
nav::Result<std::vector<nav::calibration::RecordedPose>> read_poses_option(const CalibOptions& options);

/// Prints an init-time error as "navtool calib: <describe>" and returns exit_bad_input.
int report_error(const nav::Error& error);

}  // namespace navtool
