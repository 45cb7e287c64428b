// navtool calib handeye: hand-eye calibration (AX = XB) of a camera on a tracked marker from
// row-matched marker poses and camera-to-target poses; writes the marker-to-camera joint.
#include <cstdio>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/calibration/hand_eye_calibration.hpp"
#include "nav/calibration/pose_csv.hpp"

namespace navtool {

int calib_handeye(const std::vector<std::string>& args) {
  const auto options =
      CalibOptions::parse(args, {"--marker-poses", "--camera-poses", "--tool", "--urdf", "--out", "--joint"});
  if (!options) return exit_bad_input;
  if (!options->has("--marker-poses") || !options->has("--camera-poses")) {
    return report_error({"--marker-poses FILE.csv and --camera-poses FILE.csv are required", "", 0, ""});
  }
  auto markers = nav::calibration::read_pose_csv(options->get("--marker-poses"));
  if (!markers) return report_error(markers.error());
  auto cameras = nav::calibration::read_pose_csv(options->get("--camera-poses"));
  if (!cameras) return report_error(cameras.error());
  auto result =
      nav::calibration::hand_eye_calibration(nav::calibration::poses_of(markers.value(), options->get("--tool")),
                                             nav::calibration::poses_of(cameras.value(), ""));
  if (!result) return report_error(result.error());
  const auto& x = result.value().marker_from_camera;
  const Eigen::Quaterniond q(x.rotation());
  std::printf("marker from camera: t %.6f %.6f %.6f m, q %.6f %.6f %.6f %.6f\n", x.translation().x(),
              x.translation().y(), x.translation().z(), q.w(), q.x(), q.y(), q.z());
  std::printf("AX-XB residuals over %zu motions: RMS %.4f deg, %.4f mm\n", result.value().motions,
              result.value().rms_rotation_residual_rad * 180.0 / M_PI, result.value().rms_translation_residual_m * 1e3);
  if (!options->has("--urdf")) return exit_ok;
  return write_calibration(*options, options->get("--joint", "camera_marker_to_camera"), x,
                           result.value().rms_translation_residual_m);
}

}  // namespace navtool
