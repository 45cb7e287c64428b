#pragma once
// An ultrasound source read through OpenCV's capture (videoio): a frame grabber or camera by
// device index, a video file, or an image sequence (a printf pattern such as
// "frames/%04d.png"). Each grabbed frame becomes a grey 8-bit UltrasoundFrame (optionally
// clipped to the rectangle that holds the ultrasound image, as a grabber sees the scanner's
// whole screen), with the pixel spacing of the options, stamped by the capture's clock at
// grab time, and is published on nav/ultrasound_frame. The probe's image-plane calibration
// is not part of the sample: it is the frame tree's probe -> image joint (calibration/).
// I/O-thread code (OpenCV decodes into its own buffers). No OpenCV header here.
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/samples.hpp"

namespace nav::ultrasound {

/// A rectangle of the grabbed image in pixels; width or height 0 means the whole image.
struct ClipRectangle {
  std::uint32_t x_px = 0;
  std::uint32_t y_px = 0;
  std::uint32_t width_px = 0;
  std::uint32_t height_px = 0;
};

/// How grabbed frames become samples.
struct CaptureOptions {
  std::uint32_t probe_tool_id = 2;                        ///< stamped on the frames
  std::array<double, 2> pixel_spacing_m{0.3e-3, 0.3e-3};  ///< along a row (x), along a column (y)
  ClipRectangle clip;
};

/// One opened capture; frames are read in order until the stream ends.
class CaptureSource {
 public:
  /// Opens `source`: all digits -> the Video4Linux device of that index (/dev/videoN);
  /// otherwise a video file or an image-sequence pattern. Errors name the source (missing
  /// file or device, bad options).
  static Result<std::unique_ptr<CaptureSource>> open(const std::string& source, const CaptureOptions& options,
                                                     Clock& clock);
  ~CaptureSource();
  CaptureSource(const CaptureSource&) = delete;
  CaptureSource& operator=(const CaptureSource&) = delete;

  /// Grabs the next frame into `frame` (stamped with the clock's time at the grab, numbered
  /// from 0). False at the end of the stream; an error for a frame that does not fit the
  /// clip rectangle or the sample.
  Result<bool> next(dds::UltrasoundFrame& frame);

  /// Grabs the next frame and writes it on `node` (which has advertised the frame topic).
  /// False at the end of the stream; an error if the frame is bad or DDS refused it.
  Result<bool> publish_next(dds::DdsNode& node);

  /// Frames delivered so far.
  std::uint64_t frames_read() const noexcept;

 private:
  struct Impl;
  explicit CaptureSource(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace nav::ultrasound
