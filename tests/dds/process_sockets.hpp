#pragma once
// The IP sockets this process owns, read from /proc: their protocol and local address, so
// tests can prove that DDS binds nothing but the addresses it was told to.
#include <dirent.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace nav::dds::testing {

/// One socket of this process: "udp", "tcp", "udp6" or "tcp6", and its local address as
/// the kernel lists it (IPv4: 8 hex digits in host byte order, then ":port").
struct ProcessSocket {
  std::string protocol;
  std::string local_address;
  std::uint32_t local_ipv4 = 0;  // host byte order; IPv4 sockets only
  unsigned port = 0;
};

/// The inodes of the sockets open in this process.
inline std::set<std::string> socket_inodes() {
  std::set<std::string> inodes;
  DIR* fds = opendir("/proc/self/fd");
  if (fds == nullptr) return inodes;
  while (const dirent* entry = readdir(fds)) {
    char target[128] = {};
    const std::string path = std::string("/proc/self/fd/") + entry->d_name;
    const ssize_t length = readlink(path.c_str(), target, sizeof(target) - 1);
    const std::string link(target, length > 0 ? static_cast<std::size_t>(length) : 0);
    if (link.rfind("socket:[", 0) == 0) inodes.insert(link.substr(8, link.size() - 9));
  }
  closedir(fds);
  return inodes;
}

/// Every IP socket of this process, from /proc/self/net/{udp,tcp,udp6,tcp6}.
inline std::vector<ProcessSocket> process_sockets() {
  const std::set<std::string> inodes = socket_inodes();
  std::vector<ProcessSocket> sockets;
  for (const char* protocol : {"udp", "tcp", "udp6", "tcp6"}) {
    std::ifstream table(std::string("/proc/self/net/") + protocol);
    std::string line;
    std::getline(table, line);  // header
    while (std::getline(table, line)) {
      std::istringstream fields(line);
      std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
      fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
      if (inodes.count(inode) == 0) continue;
      ProcessSocket socket{protocol, local, 0, 0};
      const std::size_t colon = local.find(':');
      socket.port = static_cast<unsigned>(std::stoul(local.substr(colon + 1), nullptr, 16));
      if (colon == 8) socket.local_ipv4 = static_cast<std::uint32_t>(std::stoul(local.substr(0, 8), nullptr, 16));
      sockets.push_back(socket);
    }
  }
  return sockets;
}

}  // namespace nav::dds::testing
