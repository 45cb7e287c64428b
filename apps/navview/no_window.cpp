// Window output when navview was configured without X11 (libx11-dev missing).
#include "image_output.hpp"

namespace navview {

nav::Result<std::unique_ptr<ImageOutput>> open_window(const std::string&) {
  return nav::Error{.message = "navview was built without X11 (install libx11-dev and reconfigure); use --headless"};
}

}  // namespace navview
