#include "nav/trackers/camera_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace nav::trackers {

Result<CameraIntrinsics> read_camera_intrinsics(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    return Error{.message = "cannot read the camera intrinsics (navtool calib camera --out writes them)", .file = path};
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream numbers(line);
    double v[9];
    for (double& value : v)
      if (!(numbers >> value) || !std::isfinite(value))
        return Error{.message = "expected the nine finite numbers fx_px fy_px cx_px cy_px k1 k2 p1 p2 k3",
                     .file = path,
                     .line = line_number};
    if (!(v[0] > 0.0) || !(v[1] > 0.0))
      return Error{.message = "the focal lengths fx_px and fy_px must be positive",
                   .file = path,
                   .line = line_number,
                   .field = "fx_px"};
    CameraIntrinsics camera;
    camera.fx_px = v[0];
    camera.fy_px = v[1];
    camera.cx_px = v[2];
    camera.cy_px = v[3];
    camera.distortion = {v[4], v[5], v[6], v[7], v[8]};
    return camera;
  }
  return Error{.message = "no intrinsics line (only comments or nothing)", .file = path, .line = line_number};
}

}  // namespace nav::trackers
