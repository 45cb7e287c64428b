#include "nav/dds/participant_qos.hpp"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>

#include <filesystem>
#include <memory>
#include <string>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

namespace nav::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

/// The address as a UDPv4 locator with port 0 (Fast DDS then derives the ports), or an
/// Error when it is not a specific unicast IPv4 address.
Result<rtps::Locator_t> unicast_locator(const std::string& address, const char* field) {
  in_addr parsed{};
  if (inet_pton(AF_INET, address.c_str(), &parsed) != 1) {
    return Error{.message = "'" + address + "' is not an IPv4 address (write it as a.b.c.d)", .field = field};
  }
  rtps::Locator_t locator;
  locator.kind = LOCATOR_KIND_UDPv4;
  rtps::IPLocator::setIPv4(locator, address);
  if (rtps::IPLocator::isAny(locator)) {
    return Error{.message = "0.0.0.0 would bind every interface; name one address", .field = field};
  }
  if (rtps::IPLocator::isMulticast(locator)) {
    return Error{.message = "'" + address + "' is a multicast address; the station uses unicast only", .field = field};
  }
  return locator;
}

/// Why `address` cannot carry the UDP transport, or empty when it can: it must be assigned
/// to an interface of this host that is up and running (has a carrier). Fast DDS silently
/// drops a whitelisted interface that is not running, and the participant would then run
/// with no UDP transport at all.
std::string interface_problem(const std::string& text, const in_addr& address) {
  ifaddrs* interfaces = nullptr;
  if (getifaddrs(&interfaces) != 0) return "the host's interfaces cannot be listed";
  std::string problem = "'" + text + "' is not an address of this host's interfaces";
  for (const ifaddrs* entry = interfaces; entry != nullptr; entry = entry->ifa_next) {
    if (entry->ifa_addr == nullptr || entry->ifa_addr->sa_family != AF_INET) continue;
    if (reinterpret_cast<const sockaddr_in*>(entry->ifa_addr)->sin_addr.s_addr != address.s_addr) continue;
    const unsigned flags = entry->ifa_flags;
    if ((flags & IFF_UP) == 0) {
      problem = "interface " + std::string(entry->ifa_name) + " holding '" + text +
                "' is down; Fast DDS would drop the UDP transport";
    } else if ((flags & IFF_RUNNING) == 0) {
      problem = "interface " + std::string(entry->ifa_name) + " holding '" + text +
                "' has no carrier (not running); Fast DDS would drop the UDP transport";
    } else {
      problem.clear();
      break;
    }
  }
  freeifaddrs(interfaces);
  return problem;
}

/// Applies the XML profile named in `config` to `qos`, or returns why it cannot.
Status apply_xml_profile(const NetworkConfig& config, fdds::DomainParticipantQos& qos) {
  if (config.xml_profile_file.empty()) {
    if (!config.xml_profile_name.empty())
      return Error{.message = "a profile name was given without a profile file", .field = "xml_profile_file"};
    return Done{};
  }
  if (config.xml_profile_name.empty()) {
    return Error{
        .message = "no participant profile named", .file = config.xml_profile_file, .field = "xml_profile_name"};
  }
  std::error_code ignored;
  if (!std::filesystem::is_regular_file(config.xml_profile_file, ignored)) {
    return Error{.message = "DDS profile file not found (no fallback to the library defaults)",
                 .file = config.xml_profile_file};
  }
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  if (factory->load_XML_profiles_file(config.xml_profile_file) != ReturnCode_t::RETCODE_OK) {
    return Error{.message = "DDS profile file could not be parsed", .file = config.xml_profile_file};
  }
  if (factory->get_participant_qos_from_profile(config.xml_profile_name, qos) != ReturnCode_t::RETCODE_OK) {
    return Error{.message = "no participant profile '" + config.xml_profile_name + "' in the file",
                 .file = config.xml_profile_file,
                 .field = "xml_profile_name"};
  }
  return Done{};
}

/// Adds the DDS Security plugins and the files of `security` (checked) to `qos`.
Status apply_security(const SecurityFiles& security, fdds::DomainParticipantQos& qos) {
  if (const Status complete = check_security(security); !complete) return complete;
  if (!security.enabled()) return Done{};
  const auto uri = [](const std::string& path) {
    std::error_code ignored;
    return "file://" + std::filesystem::absolute(path, ignored).string();
  };
  auto& properties = qos.properties().properties();
  const auto set = [&properties](const std::string& name, const std::string& value) {
    properties.emplace_back(name, value);
  };
  set("dds.sec.auth.plugin", "builtin.PKI-DH");
  set("dds.sec.auth.builtin.PKI-DH.identity_ca", uri(security.ca));
  set("dds.sec.auth.builtin.PKI-DH.identity_certificate", uri(security.certificate));
  set("dds.sec.auth.builtin.PKI-DH.private_key", uri(security.private_key));
  set("dds.sec.access.plugin", "builtin.Access-Permissions");
  set("dds.sec.access.builtin.Access-Permissions.permissions_ca", uri(security.ca));
  set("dds.sec.access.builtin.Access-Permissions.governance", uri(security.governance));
  set("dds.sec.access.builtin.Access-Permissions.permissions", uri(security.permissions));
  set("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  return Done{};
}

}  // namespace

Status check_network(const NetworkConfig& config) {
  auto local = unicast_locator(config.local_address, "local_address");
  if (!local) return local.error();
  in_addr local_address{};
  inet_pton(AF_INET, config.local_address.c_str(), &local_address);
  if (const std::string problem = interface_problem(config.local_address, local_address); !problem.empty()) {
    return Error{.message = problem, .field = "local_address"};
  }
  for (const std::string& peer : config.peer_addresses) {
    auto locator = unicast_locator(peer, "peer_addresses");
    if (!locator) return locator.error();
  }
  return Done{};
}

Status check_security(const SecurityFiles& security) {
  if (!security.enabled()) return Done{};
  struct File {
    const std::string& path;
    const char* key;
  };
  const File files[] = {{security.ca, "security.ca"},
                        {security.certificate, "security.certificate"},
                        {security.private_key, "security.private_key"},
                        {security.governance, "security.governance"},
                        {security.permissions, "security.permissions"}};
  for (const File& file : files) {
    std::error_code ignored;
    if (file.path.empty())
      return Error{.message = "DDS Security needs all five files; this one is not given", .field = file.key};
    if (!std::filesystem::is_regular_file(file.path, ignored))
      return Error{.message = "DDS Security file not found", .file = file.path, .field = file.key};
  }
  return Done{};
}

constexpr std::uint32_t kAnnouncementPeriodNs = 500'000'000;

Result<fdds::DomainParticipantQos> make_participant_qos(const NetworkConfig& config) {
  fdds::DomainParticipantQos qos;
  if (const Status xml = apply_xml_profile(config, qos); !xml) return xml.error();
  if (const Status usable = check_network(config); !usable) return usable.error();
  if (const Status secured = apply_security(config.security, qos); !secured) return secured.error();
  const rtps::Locator_t local = unicast_locator(config.local_address, "local_address").value();

  auto& transport = qos.transport();
  transport.use_builtin_transports = false;
  transport.user_transports.clear();
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList = {config.local_address};
  udp->maxInitialPeersRange = config.max_participants_per_host;
  transport.user_transports.push_back(udp);
  if (config.shared_memory) {
    auto shm = std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>();
    shm->segment_size(config.shared_memory_segment_bytes);
    transport.user_transports.push_back(shm);
  }

  auto& builtin = qos.wire_protocol().builtin;
  builtin.discovery_config.discoveryProtocol = eprosima::fastrtps::rtps::DiscoveryProtocol_t::SIMPLE;
  // A participant that started before another has sent its initial announcements already and
  // is found at its next periodic one (3 s by default): every 0.5 s here, so that a station,
  // its devices and its displays find each other within about half a second in any order.
  builtin.discovery_config.leaseDuration_announcementperiod = eprosima::fastrtps::Duration_t(0, kAnnouncementPeriodNs);
  builtin.metatrafficMulticastLocatorList.clear();
  builtin.metatrafficUnicastLocatorList.clear();
  builtin.metatrafficUnicastLocatorList.push_back(local);
  builtin.initialPeersList.clear();
  builtin.initialPeersList.push_back(local);
  for (const std::string& peer : config.peer_addresses)
    builtin.initialPeersList.push_back(unicast_locator(peer, "peer_addresses").value());
  // User data: no multicast; unicast locators come from the transports above (the
  // whitelisted address and, with shared memory, this host's segment).
  qos.wire_protocol().default_multicast_locator_list.clear();
  qos.wire_protocol().default_unicast_locator_list.clear();
  if (config.xml_profile_file.empty()) qos.name(config.participant_name);
  return qos;
}

}  // namespace nav::dds
