// navtool calib camera: camera intrinsics and lens distortion (Zhang, Brown-Conrady k1 k2 p1
// p2, and k3 with --k3 1) from a folder of PGM frames of an AprilTag board (tag36h11 ids
// 0..cols*rows-1, row-major, centred grid of the given pitch); writes
// "fx_px fy_px cx_px cy_px k1 k2 p1 p2 k3 rms_px" to --out.
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/calibration/camera_calibration.hpp"
#include "nav/trackers/apriltag_tracker.hpp"

namespace navtool {

int calib_camera(const std::vector<std::string>& args) {
  const auto options =
      CalibOptions::parse(args, {"--images", "--tag-size", "--pitch", "--cols", "--rows", "--out", "--k3"});
  if (!options) return exit_bad_input;
  const std::string k3 = options->get("--k3", "0");
  if (k3 != "0" && k3 != "1") return report_error({"expected 0 or 1", "", 0, "--k3"});
  for (const char* required : {"--images", "--tag-size", "--pitch", "--cols", "--rows", "--out"}) {
    if (!options->has(required)) return report_error({"option is required", "", 0, required});
  }
  double numbers[4];
  const char* names[4] = {"--tag-size", "--pitch", "--cols", "--rows"};
  for (int i = 0; i < 4; ++i) {
    const std::string text = options->get(names[i]);
    char* end = nullptr;
    numbers[i] = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !(numbers[i] > 0.0))
      return report_error({"expected a positive number", "", 0, names[i]});
  }
  const double tag_size_m = numbers[0];
  const double pitch_m = numbers[1];
  const int cols = static_cast<int>(numbers[2]);
  const int rows = static_cast<int>(numbers[3]);
  auto files = nav::trackers::list_pgm_files(options->get("--images"));
  if (!files) return report_error(files.error());
  auto detector = nav::trackers::AprilTagTracker::create(nav::trackers::CameraIntrinsics{}, tag_size_m, {});
  if (!detector) return report_error(detector.error());
  std::vector<nav::calibration::PlanarView> views;
  for (const std::string& file : files.value()) {
    auto image = nav::trackers::read_pgm(file);
    if (!image) return report_error(image.error());
    nav::calibration::PlanarView view;
    for (const auto& seen : detector.value()->detect(image.value())) {
      if (seen.id < 0 || seen.id >= cols * rows) continue;
      const Eigen::Vector2d centre(((seen.id % cols) - 0.5 * (cols - 1)) * pitch_m,
                                   ((seen.id / cols) - 0.5 * (rows - 1)) * pitch_m);
      for (int k = 0; k < 4; ++k) {
        view.board_points_m.push_back(centre + nav::trackers::tag_corner(k, tag_size_m).head<2>());
        view.image_points_px.push_back(seen.corners_px[k]);
      }
    }
    std::printf("%s: %zu corners\n", file.c_str(), view.board_points_m.size());
    if (view.board_points_m.size() >= 8) views.push_back(std::move(view));
  }
  auto result = nav::calibration::calibrate_camera(views, {.estimate_distortion = true, .estimate_k3 = k3 == "1"});
  if (!result) return report_error(result.error());
  const auto& c = result.value();
  const auto& d = c.distortion;
  std::printf("fx %.3f fy %.3f cx %.3f cy %.3f px, reprojection RMS %.3f px over %zu views\n", c.fx_px, c.fy_px,
              c.cx_px, c.cy_px, c.rms_reprojection_px, views.size());
  std::printf("lens distortion: k1 %.6f k2 %.6f p1 %.6f p2 %.6f k3 %.6f\n", d.k1, d.k2, d.p1, d.p2, d.k3);
  std::ofstream out(options->get("--out"));
  out.precision(10);
  out << "# fx_px fy_px cx_px cy_px k1 k2 p1 p2 k3 rms_px (pixel centres at integers; Brown-Conrady as OpenCV)\n"
      << c.fx_px << " " << c.fy_px << " " << c.cx_px << " " << c.cy_px << " " << d.k1 << " " << d.k2 << " " << d.p1
      << " " << d.p2 << " " << d.k3 << " " << c.rms_reprojection_px << "\n";
  if (!out) return report_error({"cannot write the intrinsics", options->get("--out"), 0, "--out"});
  return exit_ok;
}

}  // namespace navtool
