#pragma once
// An ultrasound device and a station linked by DDS on one domain (loopback and shared
// memory only): the device's node advertises frames and poses, the station's node queues
// them in rings; plus a wait for the next frame.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "nav/dds/dds_node.hpp"
#include "nav/dds/sample_sink.hpp"

namespace nav::ultrasound::testing {

/// Both ends of one domain, matched on both sides (so that the station's readers know the
/// device's writers before the first sample); `ok` is false (with a test failure) otherwise.
struct DeviceLink {
  std::unique_ptr<dds::DdsNode> device;
  std::unique_ptr<dds::DdsNode> station;
  std::unique_ptr<dds::RingSink<dds::UltrasoundFrame, 4>> frames =
      std::make_unique<dds::RingSink<dds::UltrasoundFrame, 4>>();
  std::unique_ptr<dds::RingSink<dds::ToolPose, 16>> poses = std::make_unique<dds::RingSink<dds::ToolPose, 16>>();
  bool ok = false;
};

inline DeviceLink link_device(std::uint32_t domain_id) {
  DeviceLink link;
  dds::NetworkConfig network;
  network.domain_id = domain_id;
  network.participant_name = "nav_test_ultrasound";
  auto device = dds::DdsNode::create(network);
  auto station = dds::DdsNode::create(network);
  if (!device.ok() || !station.ok()) {
    ADD_FAILURE() << "cannot create the DDS nodes";
    return link;
  }
  link.device = std::move(device).value();
  link.station = std::move(station).value();
  link.ok = link.station->subscribe(*link.frames).ok() && link.station->subscribe(*link.poses).ok() &&
            link.device->advertise<dds::UltrasoundFrame>().ok() && link.device->advertise<dds::ToolPose>().ok() &&
            link.device->wait_for_match(dds::Topic::ultrasound_frame, 1, 10 * kNsPerSecond) &&
            link.device->wait_for_match(dds::Topic::tool_pose, 1, 10 * kNsPerSecond) &&
            link.station->wait_for_match(dds::Topic::ultrasound_frame, 1, 10 * kNsPerSecond) &&
            link.station->wait_for_match(dds::Topic::tool_pose, 1, 10 * kNsPerSecond);
  EXPECT_TRUE(link.ok) << "the device and the station did not match";
  return link;
}

/// Pops the next frame into `frame`, waiting up to two seconds; false if none came.
inline bool next_frame(DeviceLink& link, dds::UltrasoundFrame& frame) {
  for (int attempt = 0; attempt < 200; ++attempt) {
    if (link.frames->try_pop(frame)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

}  // namespace nav::ultrasound::testing
