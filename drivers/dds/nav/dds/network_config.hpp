#pragma once
// How a station process joins DDS: which domain, which single local address UDP may use,
// which other hosts it talks to, and an optional XML profile that adds settings on top.
// Plain data; participant_qos.hpp turns it into Fast DDS QoS.
#include <cstdint>
#include <string>
#include <vector>

#include "nav/core/error.hpp"

namespace nav::dds {

/// The DDS Security files of one participant: PEM certificates and key, and the governance
/// and permissions documents signed (S/MIME) by the CA. All empty: security is off. With
/// them, the participant authenticates others (PKI-DH), enforces who may read and write which
/// topic (Access-Permissions) and encrypts what the governance says (AES-GCM-GMAC).
struct SecurityFiles {
  std::string ca;           ///< the CA of identities and of permissions
  std::string certificate;  ///< this participant's identity, signed by the CA
  std::string private_key;  ///< its key (unencrypted PEM)
  std::string governance;   ///< the domain's rules, signed by the CA
  std::string permissions;  ///< what this participant may read and write, signed by the CA

  bool enabled() const {
    return !(ca.empty() && certificate.empty() && private_key.empty() && governance.empty() && permissions.empty());
  }
};

/// The network settings of one DDS participant. The defaults keep everything on this
/// machine: shared memory plus UDP on 127.0.0.1, unicast discovery, no multicast.
struct NetworkConfig {
  std::uint32_t domain_id = 0;
  std::string participant_name = "nav";
  /// The one IPv4 address UDP binds to and announces (an interface of this host).
  std::string local_address = "127.0.0.1";
  /// IPv4 addresses of the other hosts, reached by unicast discovery.
  std::vector<std::string> peer_addresses;
  /// Adds the shared-memory transport (and its segment) for peers on this host.
  bool shared_memory = true;
  std::uint32_t shared_memory_segment_bytes = 8u << 20;
  /// Participant ids probed per peer address (UDP ports); raise for many processes per host.
  std::uint32_t max_participants_per_host = 8;
  /// Optional Fast DDS XML file and the participant profile in it (which then also names
  /// the participant). The profile is applied first; the transports, locators and peers
  /// above always override it.
  std::string xml_profile_file;
  std::string xml_profile_name;
  /// DDS Security (off unless set); a set with a file missing is an error, never a fallback.
  SecurityFiles security;
};

/// Whether `config`'s addresses can be used: each a specific unicast IPv4 address, the local
/// one on an interface of this host that is up and has a carrier. An Error names the field
/// (local_address, peer_addresses); a participant is only ever created from a config that passes.
Status check_network(const NetworkConfig& config);

/// Whether `security` is off or complete: with any file given, all five must be, and each must
/// exist. An Error names the file and its scene key (security.ca, security.certificate, ...).
Status check_security(const SecurityFiles& security);

}  // namespace nav::dds
