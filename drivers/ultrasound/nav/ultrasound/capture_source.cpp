#include "nav/ultrasound/capture_source.hpp"

#include <algorithm>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

namespace nav::ultrasound {
namespace {

bool is_device_index(const std::string& source) {
  return !source.empty() && source.size() < 6 &&
         std::all_of(source.begin(), source.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// `image` as one 8-bit grey channel (colour by luminance, 16-bit scaled by 1/256).
cv::Mat to_grey8(const cv::Mat& image) {
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  if (image.channels() == 4) cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  if (grey.depth() == CV_16U) grey.convertTo(grey, CV_8U, 1.0 / 256.0);
  return grey;
}

}  // namespace

struct CaptureSource::Impl {
  std::string source;
  CaptureOptions options;
  Clock* clock = nullptr;
  cv::VideoCapture capture;
  cv::Mat grabbed;
  std::uint64_t frames = 0;
  std::unique_ptr<dds::UltrasoundFrame> sample = std::make_unique<dds::UltrasoundFrame>();
};

CaptureSource::CaptureSource(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
CaptureSource::~CaptureSource() = default;

Result<std::unique_ptr<CaptureSource>> CaptureSource::open(const std::string& source, const CaptureOptions& options,
                                                           Clock& clock) {
  if (!(options.pixel_spacing_m[0] > 0.0 && options.pixel_spacing_m[1] > 0.0)) {
    return Error{.message = "pixel spacing must be positive", .file = source, .field = "pixel_spacing_m"};
  }
  const bool device = is_device_index(source);
  const bool pattern = source.find('%') != std::string::npos;
  if (!device && !pattern && !std::filesystem::exists(source)) {
    return Error{.message = "no such video file", .file = source, .field = "source"};
  }
  auto impl = std::make_unique<Impl>();
  impl->source = source;
  impl->options = options;
  impl->clock = &clock;
  // Each kind has its backend: Video4Linux for devices (frame grabbers, cameras), OpenCV's own
  // reader for image sequences, ffmpeg for video files. Naming it spares the probing of every
  // other capture API (FireWire, GStreamer, USB vendor SDKs).
  const bool opened = device    ? impl->capture.open(std::stoi(source), cv::CAP_V4L2)
                      : pattern ? impl->capture.open(source, cv::CAP_IMAGES)
                                : impl->capture.open(source, cv::CAP_FFMPEG);
  if (!opened || !impl->capture.isOpened()) {
    return Error{.message = device ? "cannot open the capture device" : "cannot open the video file or image sequence",
                 .file = source,
                 .field = "source"};
  }
  return std::unique_ptr<CaptureSource>(new CaptureSource(std::move(impl)));
}

Result<bool> CaptureSource::next(dds::UltrasoundFrame& frame) {
  Impl& s = *impl_;
  if (!s.capture.grab()) return false;
  const TimeNs grab_time_ns = s.clock->now_ns();
  if (!s.capture.retrieve(s.grabbed) || s.grabbed.empty()) return false;
  const cv::Mat grey = to_grey8(s.grabbed);
  const std::string where = "frame " + std::to_string(s.frames);
  if (grey.type() != CV_8UC1) return Error{.message = "unsupported pixel format", .file = s.source, .field = where};
  const ClipRectangle& clip = s.options.clip;
  cv::Rect region(0, 0, grey.cols, grey.rows);
  if (clip.width_px > 0 && clip.height_px > 0) {
    region = cv::Rect(static_cast<int>(clip.x_px), static_cast<int>(clip.y_px), static_cast<int>(clip.width_px),
                      static_cast<int>(clip.height_px));
    if (region.x + region.width > grey.cols || region.y + region.height > grey.rows) {
      return Error{.message = "the clip rectangle leaves the " + std::to_string(grey.cols) + "x" +
                              std::to_string(grey.rows) + " image",
                   .file = s.source,
                   .field = where};
    }
  }
  if (static_cast<std::size_t>(region.area()) > dds::kMaxFramePixels) {
    return Error{.message = "the image has more pixels than a frame sample holds", .file = s.source, .field = where};
  }
  const cv::Mat clipped = grey(region);
  frame.sequence_number = s.frames++;
  frame.source_time_ns = grab_time_ns;
  frame.probe_tool_id = s.options.probe_tool_id;
  frame.width_px = static_cast<std::uint32_t>(region.width);
  frame.height_px = static_cast<std::uint32_t>(region.height);
  frame.pixel_spacing_m = s.options.pixel_spacing_m;
  frame.depth_m = region.height * s.options.pixel_spacing_m[1];
  for (int row = 0; row < region.height; ++row) {
    const std::uint8_t* line = clipped.ptr<std::uint8_t>(row);
    std::copy_n(line, region.width, frame.pixels.begin() + static_cast<std::ptrdiff_t>(row) * region.width);
  }
  return true;
}

Result<bool> CaptureSource::publish_next(dds::DdsNode& node) {
  Result<bool> grabbed = next(*impl_->sample);
  if (!grabbed || !grabbed.value()) return grabbed;
  if (!node.write(*impl_->sample)) {
    return Error{.message = "DDS refused the frame",
                 .file = impl_->source,
                 .field = "frame " + std::to_string(impl_->sample->sequence_number)};
  }
  return true;
}

std::uint64_t CaptureSource::frames_read() const noexcept { return impl_->frames; }

}  // namespace nav::ultrasound
