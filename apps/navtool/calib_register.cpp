// navtool calib register: patient registration of the preoperative model: paired fiducials
// (Horn/Umeyama), optionally refined by surface ICP of the model's surface to points
// collected on the organ; writes the reference-to-model joint with FRE / ICP RMS.
#include <cstdio>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/calibration/point_registration.hpp"
#include "nav/calibration/pose_csv.hpp"
#include "nav/calibration/surface_icp.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/load_mesh.hpp"

namespace navtool {
namespace {

std::optional<nav::LengthUnit> parse_unit(const std::string& name) {
  if (name == "m") return nav::LengthUnit::metre;
  if (name == "cm") return nav::LengthUnit::centimetre;
  if (name == "mm") return nav::LengthUnit::millimetre;
  return std::nullopt;
}

}  // namespace

int calib_register(const std::vector<std::string>& args) {
  const auto options = CalibOptions::parse(args, {"--model-points", "--tracked-points", "--surface", "--unit",
                                                  "--surface-points", "--urdf", "--out", "--joint"});
  if (!options) return exit_bad_input;
  if (!options->has("--model-points") || !options->has("--tracked-points")) {
    return report_error({"--model-points FILE.csv and --tracked-points FILE.csv are required", "", 0, ""});
  }
  auto model = nav::calibration::read_point_csv(options->get("--model-points"));
  if (!model) return report_error(model.error());
  auto tracked = nav::calibration::read_point_csv(options->get("--tracked-points"));
  if (!tracked) return report_error(tracked.error());
  auto fiducial = nav::calibration::register_points(model.value(), tracked.value());
  if (!fiducial) return report_error(fiducial.error());
  nav::calibration::Transform tracked_from_model = fiducial.value().target_from_source;
  double residual_m = fiducial.value().fre_rms_m;
  std::printf("fiducial registration: %zu points, FRE %.3f mm\n", model.value().size(), residual_m * 1e3);
  if (options->has("--surface")) {
    const auto unit = parse_unit(options->get("--unit", "m"));
    if (!unit) return report_error({"unit must be m, cm or mm", "", 0, "--unit"});
    auto surface = nav::load_surface(options->get("--surface"), *unit);
    if (!surface) return report_error(surface.error());
    auto points = nav::calibration::read_point_csv(options->get("--surface-points"));
    if (!points) return report_error(points.error());
    auto icp = nav::calibration::surface_icp(surface.value(), points.value(), tracked_from_model.inverse());
    if (!icp) return report_error(icp.error());
    tracked_from_model = icp.value().surface_from_points.inverse();
    residual_m = icp.value().rms_distance_m;
    std::printf("surface ICP: %zu points, %d iterations, RMS distance %.3f mm\n", points.value().size(),
                icp.value().iterations, residual_m * 1e3);
  }
  if (!options->has("--urdf")) return exit_ok;
  return write_calibration(*options, options->get("--joint", "reference_to_liver_model"), tracked_from_model,
                           residual_m);
}

}  // namespace navtool
