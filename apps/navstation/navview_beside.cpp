#include "navview_beside.hpp"

#include <cstdio>
#include <filesystem>
#include <vector>

#include "nav/core/text_file.hpp"
#include "nav/station/station_dds.hpp"

namespace navstation {

nav::Status NavviewBeside::start(const nav::station::DisplaySurface& surface) {
  if (images_dir_.empty()) return nav::Done{};
  std::error_code error;
  std::filesystem::create_directories(images_dir_, error);
  if (error)
    return nav::Error{.message = "cannot make the folder of navview's images: " + error.message(), .file = images_dir_};
  const std::string obj = (std::filesystem::path(images_dir_) / "liver_surface.obj").string();
  if (const nav::Status written = nav::write_text_file(obj, nav::station::surface_obj(surface)); !written.ok())
    return written;
  // navview ends by itself well after the run, should navstation never stop it.
  const std::string duration_s = std::to_string(static_cast<int>(seconds_) + 300);
  std::vector<std::string> args{"--headless",
                                "--out-dir",
                                images_dir_,
                                "--surface-mesh",
                                obj,
                                "--unit",
                                "m",
                                "--period-ms",
                                "500",
                                "--duration-s",
                                duration_s,
                                "--scene",
                                scene_.source_path,  // its topics, network, security
                                "--domain",
                                std::to_string(scene_.topics.domain_id)};  // the station's (--domain wins)
  auto started = ChildProcess::start("navview", args, (std::filesystem::path(images_dir_) / "navview.log").string());
  if (!started.ok()) return started.error();
  navview_.emplace(std::move(started).value());
  return nav::Done{};
}

bool NavviewBeside::stop_and_report() {
  const int exit_code = navview_ ? navview_->stop(ChildProcess::kStopGraceS) : 0;
  if (images_dir_.empty()) return true;
  int images = 0;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(images_dir_, error))
    images += entry.path().extension() == ".png" ? 1 : 0;
  std::printf("navview: %d images in %s (exit code %d)\n", images, images_dir_.c_str(), exit_code);
  return images > 0;  // navview's own exit code is reported, not the station's failure
}

}  // namespace navstation
