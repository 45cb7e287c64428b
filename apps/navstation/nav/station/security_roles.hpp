#pragma once
// The identities of a secured station's DDS participants. Each process joins as one role and
// is allowed to write and read only that role's topics; `navtool security init` makes the
// certificate and the signed permissions of every role from these tables.
#include <array>
#include <string>
#include <vector>

#include "nav/dds/network_config.hpp"
#include "nav/dds/topics.hpp"
#include "nav/station/scene.hpp"

namespace nav::station {

/// Who a participant is: the station, its devices (trackers, scanners, the simulated patient),
/// a display (navview, a bridge), or a tool (navtool record, replay, evaluate).
enum class Role { station, devices, display, tool };

inline constexpr std::array<Role, 4> kRoles{Role::station, Role::devices, Role::display, Role::tool};

/// "station", "devices", "display" or "tool": the `{role}` of a scene's security paths and the
/// common name of the role's certificate.
const char* role_name(Role role);

/// The topics a role may write and read.
struct RoleTopics {
  std::vector<dds::Topic> publish;
  std::vector<dds::Topic> subscribe;
};

/// What `role` is allowed: the station reads poses and frames and writes its outputs; devices
/// write poses, frames and the simulated truth and read the station's health; a display only
/// reads; a tool (recording and replaying sessions) reads and writes every topic.
RoleTopics role_topics(Role role);

/// The `security:` section for the folder `navtool security init DIR` makes: DIR/ca.pem,
/// DIR/governance.p7s and, by `{role}`, DIR/{role}/certificate.pem, private_key.pem, permissions.p7s.
SecuritySettings security_folder(const std::string& dir);

/// The security files of the scene's `security` for a participant of `role` (`{role}` replaced);
/// all empty when the scene has no security section.
dds::SecurityFiles security_files(const SecuritySettings& security, Role role);

}  // namespace nav::station
