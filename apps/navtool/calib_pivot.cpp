// navtool calib pivot: pivot calibration of a needle from recorded marker poses (a pose CSV or
// a DDS recording of nav/tool_pose); writes the tip into the station URDF (joint from the
// needle base to the tip).
#include <cstdio>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/calibration/pivot_calibration.hpp"

namespace navtool {

int calib_pivot(const std::vector<std::string>& args) {
  const auto options = CalibOptions::parse(args, {"--poses", "--recording", "--tool", "--urdf", "--out", "--joint"});
  if (!options) return exit_bad_input;
  auto recorded = read_poses_option(*options);
  if (!recorded) return report_error(recorded.error());
  auto result =
      nav::calibration::pivot_calibration(nav::calibration::poses_of(recorded.value(), options->get("--tool")));
  if (!result) {
    nav::Error error = result.error();
    error.file = options->get("--poses", options->get("--recording"));
    return report_error(error);
  }
  const auto& pivot = result.value();
  std::printf("tip in marker: %.6f %.6f %.6f m\npivot in tracker: %.6f %.6f %.6f m\n", pivot.tip_in_marker_m.x(),
              pivot.tip_in_marker_m.y(), pivot.tip_in_marker_m.z(), pivot.pivot_in_tracker_m.x(),
              pivot.pivot_in_tracker_m.y(), pivot.pivot_in_tracker_m.z());
  std::printf("RMS residual %.4f mm, %zu inliers, %zu outliers, angular spread %.1f deg\n", pivot.rms_residual_m * 1e3,
              pivot.inliers, pivot.outliers, pivot.angular_spread_rad * 180.0 / M_PI);
  if (!options->has("--urdf")) return exit_ok;
  // The tip joint hangs below the needle base: express the tip in the base frame.
  auto tree = nav::calibration::FrameTree::load(options->get("--urdf"));
  if (!tree) return report_error(tree.error());
  const std::string joint = options->get("--joint", "needle_base_to_tip");
  const nav::calibration::FrameJoint* tip_joint = tree.value().joint(joint);
  if (tip_joint == nullptr) return report_error({"no such joint", options->get("--urdf"), 0, joint});
  auto base_from_marker = tree.value().lookup(tip_joint->parent, "needle_marker", 0);
  if (!base_from_marker) return report_error(base_from_marker.error());
  nav::calibration::Transform base_from_tip = nav::calibration::Transform::Identity();
  base_from_tip.translation() = base_from_marker.value() * pivot.tip_in_marker_m;
  return write_calibration(*options, joint, base_from_tip, pivot.rms_residual_m);
}

}  // namespace navtool
