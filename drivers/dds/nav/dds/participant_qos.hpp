#pragma once
// Internal (includes Fast DDS): the participant QoS built in code from a NetworkConfig.
// Built-in transports are off; UDP is whitelisted to the one configured address with
// explicit unicast metatraffic locators and initial peers, so no multicast locator exists
// and no socket opens on an interface nobody named. An XML profile may add settings but
// never replaces these; a profile that cannot be loaded is an error, never a fallback.
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "nav/core/error.hpp"
#include "nav/dds/network_config.hpp"

namespace nav::dds {

/// The QoS of a participant joining with `config`, or why it cannot be built.
Result<eprosima::fastdds::dds::DomainParticipantQos> make_participant_qos(const NetworkConfig& config);

}  // namespace nav::dds
