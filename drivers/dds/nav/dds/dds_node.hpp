#pragma once
// A station process's window on DDS: one participant, configured in code for this host
// (network_config.hpp), with typed writers and readers of the station's topics. Readers
// hand validated samples to SampleSinks from DDS threads; everything else, writes
// included, belongs to the I/O thread. The real-time thread never sees this class.
// No Fast DDS header here: the participant lives behind a pointer.
#include <cstddef>
#include <memory>
#include <optional>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/network_config.hpp"
#include "nav/dds/sample_checks.hpp"
#include "nav/dds/sample_fault.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/dds/samples.hpp"
#include "nav/dds/topics.hpp"

namespace nav::dds {

/// One DDS participant with the station's topics. Sample is any type of samples.hpp.
class DdsNode {
 public:
  /// Joins the domain with `network`, or says why it cannot (bad address, missing profile,
  /// DDS refusal, an environment override: environment_guard.hpp). Creates no writer or
  /// reader yet. With DDS Security, data sharing is off. With shared memory, first removes the
  /// segments that dead participants left behind (shared_memory_cleanup.hpp).
  static Result<std::unique_ptr<DdsNode>> create(const NetworkConfig& network, const TopicQosOptions& qos = {});
  ~DdsNode();
  DdsNode(const DdsNode&) = delete;
  DdsNode& operator=(const DdsNode&) = delete;

  /// Creates the writer of Sample's topic (once).
  template <typename Sample>
  Status advertise();
  /// Publishes `sample` (I/O thread). False when not advertised or refused by DDS.
  template <typename Sample>
  bool write(const Sample& sample);

  /// Creates the reader of Sample's topic (once). Each payload is decoded through the one
  /// checked path (checked_type.hpp: what does not decode is counted as malformed); each
  /// valid sample is sized, checked, held to `window` around its arrival when one is given,
  /// time-ordered, stamped with its receive time and offered to `sink`; every verdict is
  /// counted in boundary_counts(). `sink` must outlive this node.
  template <typename Sample>
  Status subscribe(SampleSink<Sample>& sink, std::optional<ArrivalWindow> window = std::nullopt);

  /// Remote endpoints matched by this node's writer and reader of `topic`.
  std::size_t matched(Topic topic) const;
  /// Polls matched(topic) until it reaches `count` or `timeout_ns` passes; true on success.
  bool wait_for_match(Topic topic, std::size_t count, TimeNs timeout_ns) const;

  /// Waits until every reliable sample written so far is acknowledged by the matched
  /// readers, or `timeout_ns` passes; true when all were. Call before closing a node whose
  /// last samples must arrive (destroying a writer drops what is unacknowledged).
  bool wait_for_acknowledgments(TimeNs timeout_ns) const;

  /// Samples accepted and dropped by this node's readers, by reason.
  BoundaryCounts boundary_counts() const noexcept;
  /// Those of the reader of `topic` alone.
  BoundaryCounts boundary_counts(Topic topic) const noexcept;
  /// Samples of `topic` that DDS saw sent to this node's reader and never delivered (gaps in
  /// a writer's sequence: lost on the way or overwritten in a full history); 0 unsubscribed.
  std::uint64_t samples_lost(Topic topic) const;

 private:
  struct Impl;
  explicit DdsNode(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace nav::dds
