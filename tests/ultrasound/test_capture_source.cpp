// The OpenCV capture source against clips of known frames (synthetic B-mode images written
// as a PNG sequence, exact, and as an MJPG AVI, lossy): the frames arrive on DDS (real Fast
// DDS, loopback and shared memory only) with their spacing, numbering and grab timestamps.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <vector>

#include "nav/ultrasound/bmode_simulator.hpp"
#include "nav/ultrasound/capture_source.hpp"
#include "support/test_data.hpp"
#include "ultrasound_device_link.hpp"

namespace nav::ultrasound {
namespace {

constexpr int kFrames = 5;
constexpr TimeNs kFramePeriod_ns = 40 * kNsPerMs;

/// kFrames B-mode frames of a sweep across the tumour (seeded), 256 x 256.
std::vector<cv::Mat> bmode_clip() {
  const BmodeGeometry geometry;
  const BmodeScene scene = default_bmode_scene();
  BmodeSimulator simulator(geometry, scene, 21);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat frame(static_cast<int>(geometry.height_px), static_cast<int>(geometry.width_px), CV_8UC1);
    simulator.render(plane_through_tumour(geometry, scene, 0.002 * i, 0.04), frame.data);
    frames.push_back(frame);
  }
  return frames;
}

/// A fresh folder holding the clip as frame_000.png ...; returns the sequence pattern.
std::string write_png_clip(const std::vector<cv::Mat>& frames, const std::string& name) {
  const std::filesystem::path folder = nav::testing::temporary_path(name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    char file[32];
    std::snprintf(file, sizeof file, "frame_%03zu.png", i);
    EXPECT_TRUE(cv::imwrite((folder / file).string(), frames[i]));
  }
  return (folder / "frame_%03d.png").string();
}

/// Publishes the whole capture on the link, one frame per period of the simulated clock, and
/// collects what the station received.
std::vector<std::unique_ptr<dds::UltrasoundFrame>> capture_over_dds(const std::string& source,
                                                                    const CaptureOptions& options,
                                                                    std::uint32_t domain_id, SimulatedClock& clock) {
  std::vector<std::unique_ptr<dds::UltrasoundFrame>> received;
  testing::DeviceLink link = testing::link_device(domain_id);
  if (!link.ok) return received;
  auto capture = CaptureSource::open(source, options, clock);
  EXPECT_TRUE(capture.ok()) << capture.error().describe();
  if (!capture.ok()) return received;
  for (;;) {
    const Result<bool> published = capture.value()->publish_next(*link.device);
    EXPECT_TRUE(published.ok()) << published.error().describe();
    if (!published.ok() || !published.value()) break;
    // Ring of 4 frames: take each one before the next is written.
    EXPECT_TRUE(link.device->wait_for_acknowledgments(10 * kNsPerSecond));
    received.push_back(std::make_unique<dds::UltrasoundFrame>());
    if (!testing::next_frame(link, *received.back())) {
      ADD_FAILURE() << "frame " << received.size() - 1 << " did not arrive";
      received.pop_back();
      break;
    }
    clock.advance_ns(kFramePeriod_ns);
  }
  EXPECT_EQ(capture.value()->frames_read(), received.size());
  return received;
}

TEST(CaptureSource, PngSequenceArrivesExactlyOnDds) {
  const std::vector<cv::Mat> clip = bmode_clip();
  const std::string pattern = write_png_clip(clip, "nav_capture_png");
  CaptureOptions options;
  options.probe_tool_id = 4;
  options.pixel_spacing_m = {0.25e-3, 0.3e-3};
  SimulatedClock clock(7 * kNsPerSecond);
  const auto received = capture_over_dds(pattern, options, 161, clock);
  ASSERT_EQ(received.size(), static_cast<std::size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    const dds::UltrasoundFrame& frame = *received[i];
    EXPECT_EQ(frame.sequence_number, static_cast<std::uint64_t>(i));
    EXPECT_EQ(frame.source_time_ns, 7 * kNsPerSecond + i * kFramePeriod_ns);
    EXPECT_EQ(frame.probe_tool_id, 4u);
    ASSERT_EQ(frame.width_px, 256u);
    ASSERT_EQ(frame.height_px, 256u);
    EXPECT_EQ(frame.pixel_spacing_m[0], 0.25e-3);
    EXPECT_NEAR(frame.depth_m, 256 * 0.3e-3, 1e-15);
    EXPECT_EQ(std::memcmp(frame.pixels.data(), clip[i].data, 256 * 256), 0) << "frame " << i;
  }
}

TEST(CaptureSource, MjpgClipArrivesWithinTheCodecsTolerance) {
  const std::vector<cv::Mat> clip = bmode_clip();
  const std::string path = nav::testing::temporary_path("nav_capture_clip.avi");
  {
    cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25.0, clip[0].size(), false);
    ASSERT_TRUE(writer.isOpened()) << path;
    writer.set(cv::VIDEOWRITER_PROP_QUALITY, 95);
    for (const cv::Mat& frame : clip) writer.write(frame);
  }
  SimulatedClock clock(kNsPerSecond);
  const auto received = capture_over_dds(path, CaptureOptions{}, 162, clock);
  ASSERT_EQ(received.size(), static_cast<std::size_t>(kFrames));
  // JPEG at quality 95 on speckle: a few grey levels per pixel on average; a swapped or
  // shifted frame differs by ~40 (the speckle's own spread).
  for (int i = 0; i < kFrames; ++i) {
    ASSERT_EQ(received[i]->width_px, 256u);
    const cv::Mat got(256, 256, CV_8UC1, received[i]->pixels.data());
    const double mean_abs = cv::norm(got, clip[i], cv::NORM_L1) / got.total();
    const double other = cv::norm(got, clip[(i + 1) % kFrames], cv::NORM_L1) / got.total();
    const double psnr = cv::PSNR(got, clip[i]);
    std::printf("frame %d: mean |error| %.2f grey, PSNR %.1f dB (next frame: %.1f grey)\n", i, mean_abs, psnr, other);
    EXPECT_LT(mean_abs, 4.0);
    EXPECT_GT(psnr, 30.0);
    EXPECT_GT(other, 5.0 * mean_abs);
  }
}

TEST(CaptureSource, ClipRectangleKeepsTheUltrasoundImage) {
  const std::vector<cv::Mat> clip = bmode_clip();
  const std::string pattern = write_png_clip(clip, "nav_capture_clip_rect");
  CaptureOptions options;
  options.clip = {32, 16, 200, 120};
  SimulatedClock clock;
  auto capture = CaptureSource::open(pattern, options, clock);
  ASSERT_TRUE(capture.ok()) << capture.error().describe();
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  const Result<bool> grabbed = capture.value()->next(*frame);
  ASSERT_TRUE(grabbed.ok() && grabbed.value());
  ASSERT_EQ(frame->width_px, 200u);
  ASSERT_EQ(frame->height_px, 120u);
  const cv::Mat expected = clip[0](cv::Rect(32, 16, 200, 120)).clone();
  EXPECT_EQ(std::memcmp(frame->pixels.data(), expected.data, 200 * 120), 0);
  EXPECT_NEAR(frame->depth_m, 120 * 0.3e-3, 1e-15);

  options.clip = {100, 0, 200, 64};  // 100 + 200 > 256
  auto outside = CaptureSource::open(pattern, options, clock);
  ASSERT_TRUE(outside.ok());
  const Result<bool> refused = outside.value()->next(*frame);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("256x256"), std::string::npos) << refused.error().describe();
  EXPECT_EQ(refused.error().file, pattern);
}

TEST(CaptureSource, MissingFileOrDeviceIsAnErrorNamingIt) {
  SimulatedClock clock;
  const std::string missing = nav::testing::temporary_path("nav_no_such_clip.avi");
  std::filesystem::remove(missing);
  auto file = CaptureSource::open(missing, CaptureOptions{}, clock);
  ASSERT_FALSE(file.ok());
  EXPECT_EQ(file.error().file, missing);
  EXPECT_NE(file.error().describe().find("nav_no_such_clip.avi"), std::string::npos);

  const std::string no_frames = nav::testing::temporary_path("nav_no_such_folder") + "/frame_%03d.png";
  auto sequence = CaptureSource::open(no_frames, CaptureOptions{}, clock);
  ASSERT_FALSE(sequence.ok());
  EXPECT_EQ(sequence.error().file, no_frames);

  auto device = CaptureSource::open("63", CaptureOptions{}, clock);  // no /dev/video63 here
  ASSERT_FALSE(device.ok());
  EXPECT_EQ(device.error().file, "63");
  EXPECT_NE(device.error().message.find("device"), std::string::npos);

  CaptureOptions bad;
  bad.pixel_spacing_m = {0.0, 0.3e-3};
  auto spacing = CaptureSource::open(missing, bad, clock);
  ASSERT_FALSE(spacing.ok());
  EXPECT_EQ(spacing.error().field, "pixel_spacing_m");
}

}  // namespace
}  // namespace nav::ultrasound
