#pragma once
// The running station on DDS. The simulated devices have a participant of their own that
// plays the world's recording on the station's topics when each sample is due: the tracker's
// poses on nav/tool_pose (needle marker, probe marker and respiratory marker, by tool id; the
// respiratory marker as a position with an identity rotation) and the scanner's frames on
// nav/ultrasound_frame. The station's participant takes them (PoseInbox, a frame ring), its
// I/O thread finds the tumour in each frame and feeds the real-time thread's ring, and
// publishes what the real-time thread put in the StationOutbox (nav/target_prediction,
// nav/needle_state, nav/station_health) and, at a display rate, the deformed liver surface it
// rebuilds from the published reduced state (nav/deformed_surface; display_surface.hpp).
// Positions are in the model frame. Every topic takes the name the scene gives it (`topics:`). Both participants keep
// to the project's network rules (NetworkConfig's defaults: shared memory and UDP on 127.0.0.1, no multicast). The
// devices' participant may go away for a while (PeerOutage): the station notices the lost writers, the loop degrades on
// stale input, and both recover when it comes back.
#include <cstdint>
#include <memory>
#include <optional>

#include "nav/core/error.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/pose_inbox.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/dds/samples.hpp"
#include "nav/dds/station_outbox.hpp"
#include "nav/dds/topics.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/security_roles.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/station_run.hpp"
#include "nav/station/tracker_registration.hpp"

namespace nav::station {

/// A received ToolPose as the loop's sample in the model frame (measured at its source time +
/// `device_to_loop_ns`, delivered at `received_ns`), its role by `tools`; nothing for a tool of
/// no role, for the reference tool (which `registration` takes) and for a pose before the
/// registration has its reference (counted there).
std::optional<DeviceSample> device_sample_of(const dds::ToolPose& pose, TimeNs device_to_loop_ns, TimeNs received_ns,
                                             const ToolIds& tools, TrackerRegistration& registration);

/// The station's pose inbox: the tools of `tools`' roles, the reference first (so that a poll
/// registers before it converts), within `bounds`.
std::unique_ptr<dds::PoseInbox> role_inbox(const ToolIds& tools, const dds::PoseBounds& bounds);

/// The scene's topic names, by DDS topic (what the station's participants create).
dds::TopicNames topic_names(const TopicSettings& topics);

/// The network config of a participant of `role` on `domain_id` with the scene's `network` (its
/// local address, peers and security; the project's rules otherwise: shared memory and UDP, no
/// multicast).
dds::NetworkConfig station_network(std::uint32_t domain_id, const char* participant_name,
                                   const NetworkSettings& network = {}, Role role = Role::station);

/// What a process beside the station needs to join a scene's DDS as `role`: the network (domain,
/// local address, peers, security) and the topics' names.
struct SceneDds {
  dds::NetworkConfig network;
  dds::TopicNames names{};
};

/// The DDS side of the scene at `scene_path` for a participant of `role`, or why it does not load.
Result<SceneDds> scene_dds(const std::string& scene_path, Role role);

/// A participant of `role` for one side of a run, on `domain_id`, on `network`, with the topics
/// named by `names` (empty entries: the default names).
Result<std::unique_ptr<dds::DdsNode>> make_station_node(std::uint32_t domain_id, const char* participant_name,
                                                        const dds::TopicNames& names = {},
                                                        const NetworkSettings& network = {}, Role role = Role::station);

/// The devices' and the station's participants of a run, created and matched before the
/// run starts (so that no sample is lost to discovery), with the station's sinks.
struct StationDdsLink {
  std::unique_ptr<dds::PoseInbox> poses;
  std::unique_ptr<dds::RingSink<dds::UltrasoundFrame, 4>> frames =
      std::make_unique<dds::RingSink<dds::UltrasoundFrame, 4>>();
  std::unique_ptr<dds::DdsNode> station;  ///< after the sinks: destroyed before them
  std::unique_ptr<dds::DdsNode> devices;  ///< the in-process simulated devices (none when they are other processes)
  std::uint32_t domain_id = 0;
  dds::TopicNames names{};  ///< the topics' names on the wire (empty entries: the defaults)
  NetworkSettings network;  ///< the participants' local address and peers
  ToolIds tools;            ///< the tracked tools' ids

  /// Creates the station's participant on `domain_id` with the topics named by `names`: it
  /// subscribes to poses and frames and advertises its outputs, refusing poses and frames
  /// stamped outside `arrival`, poses outside `pose_bounds` (sample_checks.hpp) and of tools
  /// other than `tools`'. With
  /// simulated devices, also their participant in this process, advertising poses and frames,
  /// and waits (up to 10 s) for the match; without, the devices are other processes.
  static Result<std::unique_ptr<StationDdsLink>> create(std::uint32_t domain_id, const dds::TopicNames& names = {},
                                                        const dds::ArrivalWindow& arrival = {},
                                                        const dds::PoseBounds& pose_bounds = {},
                                                        bool with_simulated_devices = true,
                                                        const NetworkSettings& network = {}, const ToolIds& tools = {});
};

}  // namespace nav::station
