#pragma once
// navbench dds: one-way DDS latency of poses and 1 MiB ultrasound frames, in one process
// and across two (the second one is this program again, as "navbench dds-peer"), with and
// without data-sharing, and frame throughput.
#include <cstdint>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/dds/dds_node.hpp"

namespace navbench {

/// The stream a publisher sends during one measurement.
enum class Stream { pose, frame };

/// One publisher's job: what to send, how many, how often (0: as fast as possible), where.
struct PublishPlan {
  Stream stream = Stream::pose;
  std::uint32_t domain_id = 140;
  std::uint64_t samples = 0;
  nav::TimeNs period_ns = 0;
  bool data_sharing = true;
  std::string security_dir;  ///< a `navtool security init` folder: the reader joins as station, the writer as devices
                             ///< (empty: off)
};

/// The participant a measurement's `role` ("station" reads, "devices" writes) joins with.
nav::dds::NetworkConfig bench_network(const PublishPlan& plan, const char* participant_name, bool writer);

/// Advertises the plan's topic on `node`, waits for a reader, then sends the samples,
/// each stamped with its send time. Returns false when no reader showed up.
bool publish_stream(nav::dds::DdsNode& node, const PublishPlan& plan);

/// The plan as "navbench dds-peer" arguments, and back (false on malformed arguments).
std::vector<std::string> to_peer_arguments(const PublishPlan& plan);
bool from_peer_arguments(const std::vector<std::string>& args, PublishPlan& plan);

/// navbench dds --json FILE [--domain D] [--pose-samples N] [--frame-samples N] [--security DIR]
int run_dds_bench(const std::vector<std::string>& args);
/// navbench dds-peer STREAM DOMAIN SAMPLES PERIOD_NS DATA_SHARING SECURITY_DIR|-: the publishing process.
int run_dds_peer(const std::vector<std::string>& args);

}  // namespace navbench
