// Headless output: one PNG file per composite, numbered in order.
#include <cstdio>
#include <filesystem>

#include "image_output.hpp"
#include "nav/view/png_file.hpp"

namespace navview {
namespace {

/// The numbered PNG files of one run in one directory.
class PngSequence final : public ImageOutput {
 public:
  explicit PngSequence(std::filesystem::path directory) : directory_(std::move(directory)) {}

  nav::Status show(const cv::Mat& image) override {
    char name[32];
    std::snprintf(name, sizeof(name), "navview_%06u.png", ++written_);
    return nav::view::write_png((directory_ / name).string(), image);
  }

 private:
  std::filesystem::path directory_;
  unsigned written_ = 0;
};

}  // namespace

nav::Result<std::unique_ptr<ImageOutput>> open_png_sequence(const std::string& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error || !std::filesystem::is_directory(directory)) {
    return nav::Error{
        .message = "cannot create the output directory: " + error.message(), .file = directory, .field = "--out-dir"};
  }
  return std::unique_ptr<ImageOutput>(new PngSequence(directory));
}

}  // namespace navview
