#pragma once
// navview beside the station when --images asks: headless, on the station's topics by the
// scene's names, writing PNG composites of the deformed liver, the B-mode frame and the
// predicted tumour into a folder (with the liver's rest surface as DIR/liver_surface.obj).
#include <optional>
#include <string>

#include "child_process.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/scene.hpp"

namespace navstation {

/// navview as a child process of a running station (nothing when no folder is asked for).
class NavviewBeside {
 public:
  NavviewBeside(const nav::station::Scene& scene, std::string images_dir, double seconds)
      : scene_(scene), images_dir_(std::move(images_dir)), seconds_(seconds) {}

  /// Starts navview on the station's topics with the liver's surface (a BeforeRun).
  nav::Status start(const nav::station::DisplaySurface& surface);

  /// Stops navview and reports its images; false when it wrote none.
  bool stop_and_report();

 private:
  const nav::station::Scene& scene_;
  std::string images_dir_;
  double seconds_ = 0.0;
  std::optional<ChildProcess> navview_;
};

}  // namespace navstation
