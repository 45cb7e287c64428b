#pragma once
// A stand-in for a running station, for the tests of the device processes (header-only): a
// participant that reads one topic and publishes the station's health, for which a device
// waits before it plays (with the writers its reader has matched, as a station's health says).
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "nav/dds/dds_node.hpp"

namespace nav::testing {

/// Reads `Sample` on `domain` into a ring of `Capacity` and says it runs.
template <typename Sample, std::size_t Capacity>
class StationStandIn {
 public:
  explicit StationStandIn(std::uint32_t domain) {
    dds::NetworkConfig network;
    network.domain_id = domain;
    network.participant_name = "station_stand_in";
    auto created = dds::DdsNode::create(network);
    EXPECT_TRUE(created.ok());
    if (!created.ok()) return;
    node_ = std::move(created).value();
    EXPECT_TRUE(node_->subscribe(*sink_).ok());
    EXPECT_TRUE(node_->advertise<dds::StationHealth>().ok());
  }

  /// Publishes the station's health every 20 ms (its reader's matched writers in it) and collects
  /// samples until `done(received)`
  /// holds (checked after each drain) or `timeout` passed.
  template <typename Done>
  std::vector<std::unique_ptr<Sample>> collect(Done done, std::chrono::seconds timeout) {
    std::vector<std::unique_ptr<Sample>> received;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (node_ && std::chrono::steady_clock::now() < deadline) {
      dds::StationHealth health;
      health.pose_writers = static_cast<std::uint32_t>(node_->matched(dds::Topic::tool_pose));
      health.frame_writers = static_cast<std::uint32_t>(node_->matched(dds::Topic::ultrasound_frame));
      node_->write(health);
      auto sample = std::make_unique<Sample>();
      while (sink_->try_pop(*sample)) {
        received.push_back(std::move(sample));
        sample = std::make_unique<Sample>();
      }
      if (done(received)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return received;
  }

 private:
  std::unique_ptr<dds::RingSink<Sample, Capacity>> sink_ = std::make_unique<dds::RingSink<Sample, Capacity>>();
  std::unique_ptr<dds::DdsNode> node_;
};

}  // namespace nav::testing
