#pragma once
// What the bridge tests share (header-only): the demo scene with an openigtlink section on a
// domain of the test's own, a bridge running for a scope, and waiting for a condition (the
// OpenIGTLink messages: ../igtl/igtl_test_messages.hpp).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "../igtl/igtl_test_messages.hpp"
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

}  // namespace nav::testing
