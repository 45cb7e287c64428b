// With the station's participant QoS, DDS stays where it was told: every socket of the
// process is bound to the one named address (127.0.0.1 here), none to 0.0.0.0, none to a
// multicast group, none on IPv6, even with peers of other hosts named.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include "dds_test_samples.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/pose_inbox.hpp"
#include "process_sockets.hpp"

namespace nav::dds {
namespace {

using namespace testing;

/// Runs a publisher and a subscriber node with `network` until a pose goes through, then
/// checks every socket of the process.
void expect_only_loopback_sockets(const NetworkConfig& network) {
  auto tracker = DdsNode::create(network);
  ASSERT_TRUE(tracker.ok()) << tracker.error().describe();
  auto station = DdsNode::create(network);
  ASSERT_TRUE(station.ok()) << station.error().describe();
  PoseInbox inbox{1};
  ASSERT_TRUE(tracker.value()->advertise<ToolPose>().ok());
  ASSERT_TRUE(station.value()->subscribe(inbox).ok());
  ASSERT_TRUE(station.value()->wait_for_match(Topic::tool_pose, 1, 10 * kNsPerSecond));
  TimeNs time_ns = 1;
  ASSERT_TRUE(wait_until([&] {
    tracker.value()->write(make_pose(1, time_ns++));
    return inbox.update(0);
  }));

  in_addr loopback{};
  inet_pton(AF_INET, "127.0.0.1", &loopback);
  const std::vector<ProcessSocket> sockets = process_sockets();
  EXPECT_FALSE(sockets.empty()) << "UDP discovery should have opened sockets";
  for (const ProcessSocket& socket : sockets) {
    EXPECT_TRUE(socket.protocol == "udp" || socket.protocol == "tcp") << socket.protocol << " " << socket.local_address;
    EXPECT_EQ(socket.local_ipv4, loopback.s_addr) << socket.protocol << " socket bound to " << socket.local_address;
  }
  std::printf("%zu sockets, all on 127.0.0.1\n", sockets.size());
}

TEST(DdsNetworkSafety, SocketListingSeesASocketOnAnotherAddress) {
  const int probe = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(probe, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  inet_pton(AF_INET, "127.0.0.2", &address.sin_addr);
  ASSERT_EQ(::bind(probe, reinterpret_cast<const sockaddr*>(&address), sizeof(address)), 0);
  const std::vector<ProcessSocket> sockets = process_sockets();
  ::close(probe);
  ASSERT_EQ(sockets.size(), 1u);
  EXPECT_EQ(sockets[0].protocol, "udp");
  EXPECT_EQ(sockets[0].local_ipv4, address.sin_addr.s_addr);
}

TEST(DdsNetworkSafety, LoopbackNodesBindOnlyLoopback) { expect_only_loopback_sockets(local_network(120)); }

TEST(DdsNetworkSafety, NamedPeersAddNoListeningAddress) {
  NetworkConfig network = local_network(121);
  network.peer_addresses = {"127.0.0.2", "127.0.0.3"};  // other "hosts", still on lo
  expect_only_loopback_sockets(network);
}

TEST(DdsNetworkSafety, BadAddressNeverFallsBackToEveryInterface) {
  NetworkConfig network = local_network(122);
  network.local_address = "0.0.0.0";
  const auto node = DdsNode::create(network);
  ASSERT_FALSE(node.ok());
  EXPECT_EQ(node.error().field, "local_address");
  EXPECT_TRUE(process_sockets().empty());
}

}  // namespace
}  // namespace nav::dds
