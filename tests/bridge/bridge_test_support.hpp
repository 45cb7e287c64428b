#pragma once
// What the bridge tests share (header-only): the demo scene with an openigtlink section on a
// domain of the test's own, a bridge running for a scope, a display as Slicer is one, and
// waiting for a condition (the OpenIGTLink messages: ../igtl/igtl_test_messages.hpp).
#include <gtest/gtest.h>
#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
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

/// A display as Slicer's OpenIGTLinkIF is one: OpenIGTLink's client socket, every message
/// kept as received, by device name, and the whole byte stream in order.
struct SlicerClient {
  ::igtl::ClientSocket::Pointer socket = ::igtl::ClientSocket::New();
  std::map<std::string, std::vector<std::uint8_t>> newest;
  std::vector<std::uint8_t> recorded;

  /// Receives one message within the socket's timeout; false when none came.
  bool receive() {
    ::igtl::MessageHeader::Pointer header = ::igtl::MessageHeader::New();
    header->InitPack();
    if (socket->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return false;
    const auto* received = static_cast<const std::uint8_t*>(header->GetPackPointer());
    std::vector<std::uint8_t> bytes(received, received + igtl::kHeaderBytes);  // as sent: Unpack() swaps them in place
    header->Unpack();
    bytes.resize(igtl::kHeaderBytes + header->GetBodySizeToRead());
    const int body = static_cast<int>(header->GetBodySizeToRead());
    if (body > 0 && socket->Receive(bytes.data() + igtl::kHeaderBytes, body) != body) return false;
    recorded.insert(recorded.end(), bytes.begin(), bytes.end());
    newest[header->GetDeviceName()] = std::move(bytes);
    return true;
  }
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
