#pragma once
// Fast DDS reads a few settings from the process's environment and working folder that would
// change a participant behind the code that configured it: ROS_DISCOVERY_SERVER (or the same
// key in the JSON file FASTDDS_ENVIRONMENT_FILE names) turns a participant into a discovery
// client of the servers it lists, at any address; FASTRTPS_DEFAULT_PROFILES_FILE and a
// DEFAULT_FASTRTPS_PROFILES.xml in the working folder load XML defaults and library-wide
// settings. The project's participants take their network from code (NetworkConfig, whose
// xml_profile_file is the one deliberate way in), so DdsNode refuses to start while any of
// them is present, and says which.
#include "nav/core/error.hpp"

namespace nav::dds {

/// An Error naming the first environment override present (variable and value, or file), or
/// Done when there is none.
Status refuse_environment_overrides();

}  // namespace nav::dds
