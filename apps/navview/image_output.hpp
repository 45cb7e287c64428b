#pragma once
// Where navview puts its composites: numbered PNG files (headless) or a window.
#include <memory>
#include <string>

#include <opencv2/core/mat.hpp>

#include "nav/core/error.hpp"
#include "nav/view/view_control.hpp"

namespace navview {

/// A destination for rendered composites, used from navview's one display thread.
class ImageOutput {
 public:
  virtual ~ImageOutput() = default;
  /// Shows or stores `image` (8-bit BGR).
  virtual nav::Status show(const cv::Mat& image) = 0;
  /// Handles pending window-system events: repaints, and the mouse and keys that move `view`
  /// (view_control.hpp); true when the view changed. Files have none.
  virtual bool poll_events(nav::view::ViewControl& /*view*/) { return false; }
  /// True once the user closed the window.
  virtual bool closed() const { return false; }
};

/// Writes each image as DIR/navview_NNNNNN.png, numbered from 1; creates DIR if needed.
nav::Result<std::unique_ptr<ImageOutput>> open_png_sequence(const std::string& directory);

/// Opens a window on $DISPLAY titled `title`, or says why it cannot (no display, or navview
/// built without X11).
nav::Result<std::unique_ptr<ImageOutput>> open_window(const std::string& title);

}  // namespace navview
