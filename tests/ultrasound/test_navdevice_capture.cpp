// navdevice capture, the scanner's image as a device process: an image sequence of known
// frames (written as PNG, exact) read through OpenCV's capture, clipped to the scene's
// rectangle, with the scene's pixel spacing, paced at the scene's rate, reaches a station's
// reader whole and in order once the station runs (the test stands for the station: it
// publishes its health). A scene that names no capture source, or a source that is missing,
// is refused with the device's name.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "dds/child_process.hpp"
#include "dds/station_stand_in.hpp"
#include "station/scene_text.hpp"
#include "support/test_data.hpp"

namespace nav::testing {
namespace {

const std::string kBin = NAV_BIN_DIR;
constexpr int kFrames = 8;
constexpr int kWidthPx = 160, kHeightPx = 120;
constexpr int kClipX = 10, kClipY = 20, kClipWidth = 100, kClipHeight = 80;

std::uint8_t pixel_of(int frame, int x, int y) { return static_cast<std::uint8_t>((x + 3 * y + 17 * frame) % 256); }

/// kFrames frames of kWidthPx x kHeightPx as frame_000.png ...; returns the sequence pattern.
std::string write_sequence() {
  const std::filesystem::path folder = temporary_path("capture_sequence");
  std::filesystem::create_directories(folder);
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat frame(kHeightPx, kWidthPx, CV_8UC1);
    for (int y = 0; y < kHeightPx; ++y)
      for (int x = 0; x < kWidthPx; ++x) frame.at<std::uint8_t>(y, x) = pixel_of(i, x, y);
    char file[32];
    std::snprintf(file, sizeof file, "frame_%03d.png", i);
    EXPECT_TRUE(cv::imwrite((folder / file).string(), frame));
  }
  return (folder / "frame_%03d.png").string();
}

/// The demo scene with its scanner the capture of `source` at 10 Hz, clipped and spaced.
std::string capture_scene(const std::string& source) {
  const std::string path = temporary_path("capture_scene.yaml");
  std::ofstream(path) << edited(
      movable_demo_text(),
      "  ultrasound:\n    kind: simulated\n    rate_hz: 20\n    target_noise_m: 0.001\n    seed: 2",
      "  ultrasound:\n    kind: capture\n    source: " + source + "\n    rate_hz: 10\n    clip_px: [" +
          std::to_string(kClipX) + ", " + std::to_string(kClipY) + ", " + std::to_string(kClipWidth) + ", " +
          std::to_string(kClipHeight) + "]\n    pixel_spacing_mm: [0.2, 0.25]");
  return path;
}

TEST(NavdeviceCapture, AnImageSequenceReachesTheStationClippedSpacedAndPaced) {
  const std::string scene = capture_scene(write_sequence());
  StationStandIn<dds::UltrasoundFrame, 16> station(183);
  ChildProcess device({kBin + "/navdevice", "capture", "--scene", scene, "--domain", "183"},
                      temporary_path("navdevice_capture.log"));
  ASSERT_TRUE(device.started());
  const std::vector<std::unique_ptr<dds::UltrasoundFrame>> received =
      station.collect([](const auto& received) { return received.size() >= kFrames; }, std::chrono::seconds(60));
  ASSERT_EQ(device.wait(std::chrono::seconds(30)), 0) << device.log();
  std::printf("%s", device.log().c_str());
  ASSERT_EQ(received.size(), static_cast<std::size_t>(kFrames)) << device.log();
  for (int i = 0; i < kFrames; ++i) {
    const dds::UltrasoundFrame& f = *received[static_cast<std::size_t>(i)];
    EXPECT_EQ(f.sequence_number, static_cast<std::uint64_t>(i));
    EXPECT_EQ(f.probe_tool_id, 2u);
    ASSERT_EQ(f.width_px, static_cast<std::uint32_t>(kClipWidth));
    ASSERT_EQ(f.height_px, static_cast<std::uint32_t>(kClipHeight));
    EXPECT_DOUBLE_EQ(f.pixel_spacing_m[0], 0.2e-3);
    EXPECT_DOUBLE_EQ(f.pixel_spacing_m[1], 0.25e-3);
    int wrong = 0;
    for (int y = 0; y < kClipHeight; ++y)
      for (int x = 0; x < kClipWidth; ++x)
        wrong += f.pixels[static_cast<std::size_t>(y * kClipWidth + x)] != pixel_of(i, kClipX + x, kClipY + y);
    EXPECT_EQ(wrong, 0) << "frame " << i;
  }
  // Paced at 10 Hz on the device's clock: 0.7 s from the first frame's grab to the last's.
  const double span_s = 1e-9 * static_cast<double>(received.back()->source_time_ns - received.front()->source_time_ns);
  EXPECT_NEAR(span_s, 0.7, 0.1);
  EXPECT_NE(device.log().find("end of the stream after"), std::string::npos);
}

TEST(NavdeviceCapture, NamesTheSourceThatIsMissing) {
  ChildProcess simulated({kBin + "/navdevice", "capture", "--scene", example_scene_path("demo.yaml"), "--no-wait"},
                         temporary_path("navdevice_capture_simulated.log"));
  EXPECT_EQ(simulated.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(simulated.log().find("devices.ultrasound is not a capture source"), std::string::npos) << simulated.log();
  ChildProcess missing(
      {kBin + "/navdevice", "capture", "--scene", capture_scene("/nonexistent/frame_%03d.png"), "--no-wait"},
      temporary_path("navdevice_capture_missing.log"));
  EXPECT_EQ(missing.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(missing.log().find("navdevice capture: "), std::string::npos) << missing.log();
  EXPECT_NE(missing.log().find("/nonexistent/frame_%03d.png"), std::string::npos) << missing.log();
}

}  // namespace
}  // namespace nav::testing
