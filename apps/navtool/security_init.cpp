// navtool security init DIR [--scene FILE] [--days N]: a test CA and, for every role of a
// secured station (security_roles.hpp), an identity and signed permissions; and the domain's
// signed governance. Made with the openssl program; the keys are unencrypted PEM, readable by
// their owner only. The files fit a scene's `security:` section with `{role}` paths:
//   DIR/ca.pem, DIR/ca_key.pem, DIR/governance.p7s (governance.xml, its text),
//   DIR/ROLE/certificate.pem, DIR/ROLE/private_key.pem, DIR/ROLE/permissions.p7s (.xml).
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "nav/core/text_file.hpp"
#include "nav/station/security_roles.hpp"
#include "nav/station/station_dds.hpp"

extern char** environ;

namespace navtool {
namespace {

namespace fs = std::filesystem;
using nav::station::Role;

constexpr int kMaxDomainId = 232;
constexpr const char* kValidFrom = "2020-01-01T00:00:00";

/// Runs `openssl args...` with its output appended to `log`; true when it exits 0.
bool openssl(const std::vector<std::string>& args, const std::string& log) {
  std::vector<char*> argv{const_cast<char*>("openssl")};
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  const int spawned = posix_spawnp(&pid, "openssl", &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (spawned != 0) return false;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// The XML list of `topics` by their names in `names`.
std::string topic_list(const std::vector<nav::dds::Topic>& topics, const nav::dds::TopicNames& names) {
  std::string xml;
  for (const nav::dds::Topic topic : topics)
    xml += "            <topic>" + std::string(nav::dds::topic_name(topic, names)) + "</topic>\n";
  return xml;
}

std::string domains_xml() {
  return "<domains><id_range><min>0</min><max>" + std::to_string(kMaxDomainId) + "</max></id_range></domains>";
}

/// The domain's rules: no unauthenticated participant, discovery and liveliness encrypted, every
/// RTPS message encrypted and authenticated, every topic read and write access-controlled.
std::string governance_xml() {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\">\n"
         "  <domain_access_rules>\n"
         "    <domain_rule>\n"
         "      " +
         domains_xml() +
         "\n"
         "      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>\n"
         "      <enable_join_access_control>true</enable_join_access_control>\n"
         "      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>\n"
         "      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>\n"
         "      <rtps_protection_kind>ENCRYPT</rtps_protection_kind>\n"
         "      <topic_access_rules>\n"
         "        <topic_rule>\n"
         "          <topic_expression>*</topic_expression>\n"
         "          <enable_discovery_protection>true</enable_discovery_protection>\n"
         "          <enable_liveliness_protection>true</enable_liveliness_protection>\n"
         "          <enable_read_access_control>true</enable_read_access_control>\n"
         "          <enable_write_access_control>true</enable_write_access_control>\n"
         "          <metadata_protection_kind>NONE</metadata_protection_kind>\n"
         "          <data_protection_kind>NONE</data_protection_kind>\n"
         "        </topic_rule>\n"
         "      </topic_access_rules>\n"
         "    </domain_rule>\n"
         "  </domain_access_rules>\n"
         "</dds>\n";
}

/// What the certificate "CN=`role`" may write and read, until `valid_until`; nothing else.
std::string permissions_xml(Role role, const nav::dds::TopicNames& names, const std::string& valid_until) {
  const nav::station::RoleTopics topics = nav::station::role_topics(role);
  const std::string name = nav::station::role_name(role);
  std::string rule = "      <allow_rule>\n        " + domains_xml() + "\n";
  if (!topics.publish.empty())
    rule += "        <publish>\n          <topics>\n" + topic_list(topics.publish, names) +
            "          </topics>\n        </publish>\n";
  if (!topics.subscribe.empty())
    rule += "        <subscribe>\n          <topics>\n" + topic_list(topics.subscribe, names) +
            "          </topics>\n        </subscribe>\n";
  rule += "      </allow_rule>\n";
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\">\n"
         "  <permissions>\n"
         "    <grant name=\"" +
         name +
         "\">\n"
         "      <subject_name>CN=" +
         name +
         "</subject_name>\n"
         "      <validity><not_before>" +
         std::string(kValidFrom) + "</not_before><not_after>" + valid_until + "</not_after></validity>\n" + rule +
         "      <default>DENY</default>\n"
         "    </grant>\n"
         "  </permissions>\n"
         "</dds>\n";
}

/// Signs `xml_path` with the CA into `p7s_path` (S/MIME, as DDS Security reads it).
bool sign(const fs::path& dir, const fs::path& xml_path, const fs::path& p7s_path, const std::string& log) {
  return openssl({"smime", "-sign", "-in", xml_path.string(), "-text", "-out", p7s_path.string(), "-signer",
                  (dir / "ca.pem").string(), "-inkey", (dir / "ca_key.pem").string()},
                 log);
}

/// An EC P-256 key at `path`, readable by its owner only.
bool make_key(const fs::path& path, const std::string& log) {
  if (!openssl({"genpkey", "-algorithm", "EC", "-pkeyopt", "ec_paramgen_curve:P-256", "-out", path.string()}, log))
    return false;
  std::error_code error;
  fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write, error);
  return !error;
}

int fail(const std::string& what, const std::string& log) {
  std::fprintf(stderr, "navtool security init: %s failed (openssl's output: %s)\n", what.c_str(), log.c_str());
  return exit_failure;
}

int fail(const nav::Error& error) {
  std::fprintf(stderr, "navtool security init: %s\n", error.describe().c_str());
  return exit_failure;
}

}  // namespace

int security_init(const std::vector<std::string>& args) {
  std::string dir_text, scene_path;
  int days = 365;
  bool understood = true;
  for (std::size_t i = 0; understood && i < args.size(); ++i) {
    const bool has_value = i + 1 < args.size();
    try {
      if (args[i] == "--scene" && has_value)
        scene_path = args[++i];
      else if (args[i] == "--days" && has_value)
        days = std::stoi(args[++i]);
      else if (dir_text.empty() && args[i].rfind("--", 0) != 0)
        dir_text = args[i];
      else
        understood = false;
    } catch (const std::exception&) {
      understood = false;
    }
  }
  if (!understood || dir_text.empty() || days < 1 || days > 36500) {
    std::fputs("usage: navtool security init DIR [--scene FILE] [--days N]\n", stderr);
    return exit_bad_input;
  }
  nav::dds::TopicNames names{};
  if (!scene_path.empty()) {
    auto scene = nav::station::scene_dds(scene_path, Role::station);
    if (!scene) {
      std::fprintf(stderr, "navtool security init: %s\n", scene.error().describe().c_str());
      return exit_bad_input;
    }
    names = scene.value().names;
  }
  const fs::path dir(dir_text);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) {
    std::fprintf(stderr, "navtool security init: cannot make %s: %s\n", dir_text.c_str(), error.message().c_str());
    return exit_failure;
  }
  const std::string log = (dir / "openssl.log").string();
  const std::string days_text = std::to_string(days);
  // The permissions end no earlier than the certificates (at the new year after them).
  const std::time_t now = std::time(nullptr);
  std::tm today{};
  gmtime_r(&now, &today);
  const std::string valid_until = std::to_string(1900 + today.tm_year + days / 365 + 1) + "-01-01T00:00:00";

  if (!make_key(dir / "ca_key.pem", log)) return fail("the CA's key", log);
  if (!openssl({"req", "-new", "-x509", "-sha256", "-key", (dir / "ca_key.pem").string(), "-out",
                (dir / "ca.pem").string(), "-days", days_text, "-subj", "/CN=navrt station CA"},
               log))
    return fail("the CA's certificate", log);
  if (const nav::Status written = nav::write_text_file((dir / "governance.xml").string(), governance_xml()); !written)
    return fail(written.error());
  if (!sign(dir, dir / "governance.xml", dir / "governance.p7s", log)) return fail("signing the governance", log);

  for (const Role role : nav::station::kRoles) {
    const std::string name = nav::station::role_name(role);
    const fs::path folder = dir / name;
    fs::create_directories(folder, error);
    const fs::path request = folder / "request.csr";
    if (error || !make_key(folder / "private_key.pem", log)) return fail("the " + name + " key", log);
    if (!openssl({"req", "-new", "-sha256", "-key", (folder / "private_key.pem").string(), "-out", request.string(),
                  "-subj", "/CN=" + name},
                 log) ||
        !openssl({"x509", "-req", "-sha256", "-in", request.string(), "-CA", (dir / "ca.pem").string(), "-CAkey",
                  (dir / "ca_key.pem").string(), "-set_serial", std::to_string(2 + static_cast<int>(role)), "-days",
                  days_text, "-out", (folder / "certificate.pem").string()},
                 log))
      return fail("the " + name + " certificate", log);
    fs::remove(request, error);
    if (const nav::Status written =
            nav::write_text_file((folder / "permissions.xml").string(), permissions_xml(role, names, valid_until));
        !written)
      return fail(written.error());
    if (!sign(dir, folder / "permissions.xml", folder / "permissions.p7s", log))
      return fail("signing the " + name + " permissions", log);
  }
  fs::remove(log, error);
  const nav::station::SecuritySettings scene = nav::station::security_folder(dir_text);
  std::printf(
      "navtool security init: a CA, the governance and the identities of station, devices, display and tool in %s\n"
      "scene:\n  security:\n    ca: %s\n    governance: %s\n    certificate: %s\n    private_key: %s\n    permissions: "
      "%s\n",
      dir_text.c_str(), scene.ca.c_str(), scene.governance.c_str(), scene.certificate.c_str(),
      scene.private_key.c_str(), scene.permissions.c_str());
  return exit_ok;
}

}  // namespace navtool
