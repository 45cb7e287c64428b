// Participant and topic QoS built in code: no built-in transports, UDP whitelisted to one
// named address with unicast-only discovery, shared memory alongside, peers as initial
// peers; bad addresses and missing XML profiles are errors, and an XML profile adds
// settings without undoing any of these. Topic QoS as the issue states it.
#include <gtest/gtest.h>

#include <ifaddrs.h>
#include <net/if.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include "nav/dds/dds_node.hpp"
#include "nav/dds/participant_qos.hpp"
#include "nav/dds/topic_qos.hpp"

namespace nav::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::IPLocator;

/// True when no locator of `list` is a multicast address.
template <typename List>
bool all_unicast(const List& list) {
  for (const auto& locator : list) {
    if (IPLocator::isMulticast(locator)) return false;
  }
  return true;
}

TEST(DdsParticipantQos, DefaultsAreLoopbackUdpPlusSharedMemoryWithUnicastDiscovery) {
  const auto qos = make_participant_qos(NetworkConfig{});
  ASSERT_TRUE(qos.ok()) << qos.error().describe();
  const auto& transport = qos.value().transport();
  EXPECT_FALSE(transport.use_builtin_transports);
  ASSERT_EQ(transport.user_transports.size(), 2u);
  const auto udp =
      std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(transport.user_transports[0]);
  ASSERT_NE(udp, nullptr);
  EXPECT_EQ(udp->interfaceWhiteList, std::vector<std::string>{"127.0.0.1"});
  const auto shm =
      std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(transport.user_transports[1]);
  ASSERT_NE(shm, nullptr);
  EXPECT_EQ(shm->segment_size(), 8u << 20);

  const auto& builtin = qos.value().wire_protocol().builtin;
  EXPECT_TRUE(builtin.metatrafficMulticastLocatorList.empty());
  ASSERT_EQ(builtin.metatrafficUnicastLocatorList.size(), 1u);
  EXPECT_EQ(IPLocator::toIPv4string(*builtin.metatrafficUnicastLocatorList.begin()), "127.0.0.1");
  ASSERT_EQ(builtin.initialPeersList.size(), 1u);
  EXPECT_EQ(IPLocator::toIPv4string(*builtin.initialPeersList.begin()), "127.0.0.1");
  EXPECT_TRUE(qos.value().wire_protocol().default_multicast_locator_list.empty());
  EXPECT_EQ(qos.value().name().to_string(), "nav");
}

TEST(DdsParticipantQos, PeersOfOtherHostsBecomeUnicastInitialPeers) {
  NetworkConfig config;
  config.peer_addresses = {"10.20.0.2", "10.20.0.3"};
  config.shared_memory = false;
  const auto qos = make_participant_qos(config);
  ASSERT_TRUE(qos.ok()) << qos.error().describe();
  EXPECT_EQ(qos.value().transport().user_transports.size(), 1u);
  const auto& peers = qos.value().wire_protocol().builtin.initialPeersList;
  ASSERT_EQ(peers.size(), 3u);
  std::vector<std::string> addresses;
  for (const auto& peer : peers) addresses.push_back(IPLocator::toIPv4string(peer));
  EXPECT_EQ(addresses, (std::vector<std::string>{"127.0.0.1", "10.20.0.2", "10.20.0.3"}));
  EXPECT_TRUE(all_unicast(peers));
}

TEST(DdsParticipantQos, AddressesThatAreNotOneNamedLocalUnicastAddressAreRefused) {
  const auto refused = [](const std::string& local, const std::string& peer, const char* field) {
    NetworkConfig config;
    config.local_address = local;
    if (!peer.empty()) config.peer_addresses = {peer};
    const auto qos = make_participant_qos(config);
    return !qos.ok() && qos.error().field == field;
  };
  EXPECT_TRUE(refused("0.0.0.0", "", "local_address"));
  EXPECT_TRUE(refused("239.255.0.1", "", "local_address"));
  EXPECT_TRUE(refused("localhost", "", "local_address"));
  EXPECT_TRUE(refused("192.0.2.77", "", "local_address"));  // TEST-NET-1: on no interface here
  EXPECT_TRUE(refused("127.0.0.1", "239.255.0.1", "peer_addresses"));
  EXPECT_TRUE(refused("127.0.0.1", "0.0.0.0", "peer_addresses"));
  EXPECT_TRUE(refused("127.0.0.1", "host-b", "peer_addresses"));
}

/// In a child process with its own network namespace (so the host's interfaces are left
/// alone) holding a veth pair whose end navdown0 (10.209.0.1) is up but has no carrier, its
/// peer being down: 0 when `check` holds, 2 when the namespace cannot be made, 1 otherwise.
template <typename Check>
int in_own_network_namespace(Check check) {
  const pid_t child = fork();
  if (child == 0) {
    if (unshare(CLONE_NEWNET) != 0) _exit(2);
    if (std::system("ip link add navdown0 type veth peer name navdown1 && ip addr add 10.209.0.1/24 dev navdown0 && "
                    "ip link set navdown0 up") != 0)
      _exit(2);
    _exit(check() ? 0 : 1);
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

/// True when an interface named `name` is listed with IFF_RUNNING.
bool is_running(const char* name) {
  ifaddrs* interfaces = nullptr;
  if (getifaddrs(&interfaces) != 0) return false;
  bool running = false;
  for (const ifaddrs* entry = interfaces; entry != nullptr; entry = entry->ifa_next) {
    if (std::strcmp(entry->ifa_name, name) == 0 && (entry->ifa_flags & IFF_RUNNING) != 0) running = true;
  }
  freeifaddrs(interfaces);
  return running;
}

/// Waits up to `timeout` for interface `name` to be running; true when it is.
bool becomes_running(const char* name, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!is_running(name)) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    usleep(10000);
  }
  return true;
}

TEST(DdsParticipantQos, AnAddressOnAnInterfaceThatIsNotRunningIsRefusedNotDropped) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root for a network namespace";
  // Fast DDS drops a whitelisted interface that is not running and would run with no UDP
  // transport: the node must refuse to start instead, naming the interface and the field.
  const int down = in_own_network_namespace([] {
    NetworkConfig config;
    config.local_address = "10.209.0.1";
    const auto qos = make_participant_qos(config);
    const auto node = DdsNode::create(config);
    std::fprintf(stderr, "refused: %s\n", qos.ok() ? "(accepted)" : qos.error().message.c_str());
    return !qos.ok() && qos.error().field == "local_address" &&
           qos.error().message.find("navdown0") != std::string::npos &&
           qos.error().message.find("no carrier") != std::string::npos && !node.ok() &&
           node.error().field == "local_address";
  });
  if (down == 2) GTEST_SKIP() << "no network namespace or veth pair here";
  EXPECT_EQ(down, 0);
  // The same address once the peer is up too (the link then has a carrier) is accepted. The
  // kernel reports the carrier asynchronously (its link watch may wait up to a second).
  const int up = in_own_network_namespace([] {
    if (std::system("ip link set navdown1 up") != 0) return false;
    if (!becomes_running("navdown0", std::chrono::seconds(5))) return false;
    NetworkConfig config;
    config.local_address = "10.209.0.1";
    return make_participant_qos(config).ok();
  });
  EXPECT_EQ(up, 0);
}

TEST(DdsParticipantQos, MissingProfileFileIsAnErrorNeverAFallback) {
  NetworkConfig config;
  config.xml_profile_file = "/nonexistent/nav_profiles.xml";
  config.xml_profile_name = "station";
  const auto qos = make_participant_qos(config);
  ASSERT_FALSE(qos.ok());
  EXPECT_NE(qos.error().describe().find("not found"), std::string::npos) << qos.error().describe();
  EXPECT_NE(qos.error().describe().find("/nonexistent/nav_profiles.xml"), std::string::npos);

  config.xml_profile_name.clear();
  EXPECT_FALSE(make_participant_qos(config).ok());
}

/// Writes `text` to a file in the test's temporary directory and returns its path.
std::string write_temp_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(DdsParticipantQos, XmlProfileAddsSettingsButCannotReopenTheNetwork) {
  const std::string path = write_temp_file("nav_dds_profile.xml", R"(<?xml version="1.0" encoding="UTF-8" ?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <participant profile_name="nav_qos_test_station">
      <rtps>
        <name>from_xml</name>
        <useBuiltinTransports>true</useBuiltinTransports>
        <builtin>
          <discovery_config><leaseDuration><sec>7</sec></leaseDuration></discovery_config>
          <metatrafficMulticastLocatorList>
            <locator><udpv4><address>239.255.0.1</address><port>7400</port></udpv4></locator>
          </metatrafficMulticastLocatorList>
        </builtin>
      </rtps>
    </participant>
  </profiles>
</dds>
)");
  NetworkConfig config;
  config.xml_profile_file = path;
  config.xml_profile_name = "nav_qos_test_station";
  const auto qos = make_participant_qos(config);
  ASSERT_TRUE(qos.ok()) << qos.error().describe();
  EXPECT_EQ(qos.value().name().to_string(), "from_xml");
  EXPECT_EQ(qos.value().wire_protocol().builtin.discovery_config.leaseDuration.seconds, 7);
  EXPECT_FALSE(qos.value().transport().use_builtin_transports);
  EXPECT_TRUE(qos.value().wire_protocol().builtin.metatrafficMulticastLocatorList.empty());

  config.xml_profile_name = "no_such_profile";
  const auto missing = make_participant_qos(config);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().field, "xml_profile_name");
}

TEST(DdsParticipantQos, UnparsableProfileFileIsAnError) {
  NetworkConfig config;
  config.xml_profile_file = write_temp_file("nav_dds_broken.xml", "<dds><profiles><participant");
  config.xml_profile_name = "station";
  const auto qos = make_participant_qos(config);
  ASSERT_FALSE(qos.ok());
  EXPECT_NE(qos.error().message.find("parsed"), std::string::npos) << qos.error().describe();
}

TEST(DdsTopicQos, PosesAreBestEffortKeepingABurstOfEveryToolWithADeadline) {
  const TopicQosOptions options;
  const auto writer = writer_qos(Topic::tool_pose, options);
  const auto reader = reader_qos(Topic::tool_pose, options);
  for (const auto* history : {&writer.history(), &reader.history()}) {
    EXPECT_EQ(history->kind, fdds::KEEP_LAST_HISTORY_QOS);
    EXPECT_EQ(history->depth, 8);  // the tools of a tracker's burst share the unkeyed topic
  }
  EXPECT_EQ(writer.reliability().kind, fdds::BEST_EFFORT_RELIABILITY_QOS);
  EXPECT_EQ(reader.reliability().kind, fdds::BEST_EFFORT_RELIABILITY_QOS);
  EXPECT_EQ(writer.deadline().period, eprosima::fastrtps::Duration_t(0, 100'000'000));
  EXPECT_EQ(reader.deadline().period, writer.deadline().period);
}

TEST(DdsTopicQos, FramesAreBestEffortKeepLastTwoThroughDataSharing) {
  TopicQosOptions options;
  const auto writer = writer_qos(Topic::ultrasound_frame, options);
  EXPECT_EQ(writer.reliability().kind, fdds::BEST_EFFORT_RELIABILITY_QOS);
  EXPECT_EQ(writer.history().depth, 2);
  EXPECT_EQ(writer.data_sharing().kind(), fdds::AUTO);
  EXPECT_EQ(reader_qos(Topic::ultrasound_frame, options).data_sharing().kind(), fdds::AUTO);
  options.data_sharing = false;
  EXPECT_EQ(writer_qos(Topic::ultrasound_frame, options).data_sharing().kind(), fdds::OFF);
}

TEST(DdsTopicQos, OutputsAreReliableLatestOnlyAndHealthIsTransientLocal) {
  const TopicQosOptions options;
  for (const Topic topic :
       {Topic::needle_state, Topic::target_prediction, Topic::deformed_surface, Topic::station_health}) {
    const auto writer = writer_qos(topic, options);
    EXPECT_EQ(writer.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS) << topic_name(topic);
    EXPECT_EQ(writer.history().kind, fdds::KEEP_LAST_HISTORY_QOS) << topic_name(topic);
    EXPECT_EQ(writer.history().depth, 1) << topic_name(topic);
    const auto durability =
        topic == Topic::station_health ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
    EXPECT_EQ(writer.durability().kind, durability) << topic_name(topic);
    EXPECT_EQ(reader_qos(topic, options).durability().kind, durability) << topic_name(topic);
    EXPECT_EQ(reader_qos(topic, options).reliability().kind, fdds::RELIABLE_RELIABILITY_QOS) << topic_name(topic);
  }
}

}  // namespace
}  // namespace nav::dds
