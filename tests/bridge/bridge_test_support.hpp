#pragma once
// What the bridge tests share (header-only): the demo scene with an openigtlink section on a
// domain of the test's own, the station's side of DDS, OpenIGTLink messages packed by
// OpenIGTLink itself, and waiting for a condition.
#include <gtest/gtest.h>
#include <igtlImageMessage.h>
#include <igtlTransformMessage.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "../station/scene_text.hpp"
#include "nav/bridge/igtl_bridge.hpp"
#include "nav/core/clock.hpp"
#include "nav/station/scene.hpp"

namespace nav::testing {

/// The demo scene on `domain_id` with `openigtlink` (the section's body, indented two spaces).
inline station::Scene bridge_scene(std::uint32_t domain_id, const std::string& openigtlink) {
  const std::string text = edited(movable_demo_text(), "domain_id: 0", "domain_id: " + std::to_string(domain_id)) +
                           "\nopenigtlink:\n" + openigtlink;
  auto scene = station::parse_scene(text, example_scene_path("bridge_test.yaml"));
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
  return scene.ok() ? std::move(scene).value() : station::Scene{};
}

/// A bridge running on a thread of its own for a scope: stopped and joined when it ends, also
/// when an assertion leaves the test early.
class RunningBridge {
 public:
  explicit RunningBridge(bridge::IgtlBridge& bridge) : bridge_(bridge), thread_([&bridge] { bridge.run(); }) {}
  ~RunningBridge() {
    bridge_.stop();
    thread_.join();
  }
  RunningBridge(const RunningBridge&) = delete;
  RunningBridge& operator=(const RunningBridge&) = delete;

 private:
  bridge::IgtlBridge& bridge_;
  std::thread thread_;
};

/// Polls `done` every 10 ms for up to `seconds`; whether it came true.
inline bool wait_until(const std::function<bool()>& done, double seconds = 10.0) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

/// The bytes of an OpenIGTLink message packed by OpenIGTLink.
inline std::vector<std::uint8_t> packed_bytes(::igtl::MessageBase& message) {
  message.Pack();
  const auto* bytes = static_cast<const std::uint8_t*>(message.GetPackPointer());
  return {bytes, bytes + message.GetPackSize()};
}

/// `time_ns` as OpenIGTLink's seconds and 2^-32 fractions.
inline void stamp_message(::igtl::MessageBase& message, TimeNs time_ns) {
  message.SetTimeStamp(static_cast<unsigned>(time_ns / kNsPerSecond),
                       static_cast<unsigned>(((time_ns % kNsPerSecond) << 32) / kNsPerSecond));
}

/// A TRANSFORM `device` of `matrix` (row-major 3x4, translation in mm), stamped `time_ns`.
inline std::vector<std::uint8_t> transform_bytes(const std::string& device, const float (&matrix)[3][4],
                                                 TimeNs time_ns) {
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  message->SetDeviceName(device.c_str());
  ::igtl::Matrix4x4 m;
  ::igtl::IdentityMatrix(m);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[r][c] = matrix[r][c];
  message->SetMatrix(m);
  stamp_message(*message, time_ns);
  return packed_bytes(*message);
}

/// An 8-bit IMAGE `device` of width x height pixels (value: (x + y) % 256) at the spacing in mm.
inline std::vector<std::uint8_t> image_bytes(const std::string& device, int width, int height, float spacing_x_mm,
                                             float spacing_y_mm, TimeNs time_ns) {
  ::igtl::ImageMessage::Pointer message = ::igtl::ImageMessage::New();
  message->SetDeviceName(device.c_str());
  message->SetDimensions(width, height, 1);
  message->SetSpacing(spacing_x_mm, spacing_y_mm, 1.0f);
  message->SetScalarTypeToUint8();
  message->AllocateScalars();
  auto* pixels = static_cast<std::uint8_t*>(message->GetScalarPointer());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) pixels[y * width + x] = static_cast<std::uint8_t>((x + y) % 256);
  stamp_message(*message, time_ns);
  return packed_bytes(*message);
}

}  // namespace nav::testing
