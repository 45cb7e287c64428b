// Several hosts: two network namespaces joined by a veth pair stand for two machines
// (10.201.0.1 and 10.201.0.2, nothing else but their loopback). navtool replays a recording
// in one, navview runs headless in the other, each naming the other as its one unicast
// peer; navview's PNG files show the scene and the frames crossed the veth link. And a live
// station with its simulated patient on one host is evaluated from the other, each process
// on the network its scene names. Needs root
// (skipped otherwise) and iproute2; the namespaces are removed afterwards, even on failure,
// and are named after the test's pid so parallel or aborted runs do not collide.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "child_process.hpp"
#include "dds_test_samples.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"
#include "nav/view/png_file.hpp"
#include "navview_placing_pose.hpp"
#include "station/scene_text.hpp"
#include "test_navview_scene.hpp"

namespace nav::dds {
namespace {

using nav::testing::ChildProcess;
using namespace nav::view::testing;

constexpr const char* kNamespacePrefix = "navhost";  // navhost<pid>a, navhost<pid>b
constexpr const char* kAddressA = "10.201.0.1";
constexpr const char* kAddressB = "10.201.0.2";

/// The path of iproute2's `ip`, or empty when it is not installed.
std::string ip_program() {
  for (const char* path : {"/usr/sbin/ip", "/sbin/ip", "/usr/bin/ip", "/bin/ip"}) {
    if (access(path, X_OK) == 0) return path;
  }
  return "";
}

/// Runs a shell command; its output, or nothing when it failed.
std::optional<std::string> run(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return std::nullopt;
  std::string output;
  char buffer[256];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  return pclose(pipe) == 0 ? std::optional<std::string>(output) : std::nullopt;
}

/// Removes the namespaces of earlier runs whose test process no longer exists.
void remove_stale_namespaces(const std::string& ip) {
  std::istringstream names(run(ip + " netns list").value_or(""));
  for (std::string name; names >> name;) {
    if (name.rfind(kNamespacePrefix, 0) != 0 || name.size() < 2) continue;
    const std::string digits =
        name.substr(std::string(kNamespacePrefix).size(), name.size() - 1 - std::string(kNamespacePrefix).size());
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    if (kill(static_cast<pid_t>(std::stol(digits)), 0) != 0 && errno == ESRCH) run(ip + " netns delete " + name);
  }
}

/// Two namespaces "hosts" a and b joined by a veth pair, removed on destruction.
class TwoHosts {
 public:
  explicit TwoHosts(std::string ip) : ip_(std::move(ip)) {
    const std::string id = std::to_string(getpid());
    host_a_ = kNamespacePrefix + id + "a";
    host_b_ = kNamespacePrefix + id + "b";
    const std::string veth_a = "nva" + id, veth_b = "nvb" + id;  // interface names: at most 15 chars
    const std::string commands[] = {
        ip_ + " netns add " + host_a_,
        ip_ + " netns add " + host_b_,
        ip_ + " link add " + veth_a + " netns " + host_a_ + " type veth peer name " + veth_b + " netns " + host_b_,
        ip_ + " -n " + host_a_ + " addr add " + kAddressA + "/24 dev " + veth_a,
        ip_ + " -n " + host_b_ + " addr add " + kAddressB + "/24 dev " + veth_b,
        ip_ + " -n " + host_a_ + " link set " + veth_a + " up",
        ip_ + " -n " + host_b_ + " link set " + veth_b + " up",
        ip_ + " -n " + host_a_ + " link set lo up",
        ip_ + " -n " + host_b_ + " link set lo up",
    };
    for (const std::string& command : commands) {
      if (!run(command)) {
        failure_ = command;
        return;
      }
    }
    veth_b_ = veth_b;
    // The link carries only once both ends are up; Fast DDS skips an interface without carrier.
    const bool up = testing::wait_until([&] { return link_up(host_a_, veth_a) && link_up(host_b_, veth_b); });
    if (!up) failure_ = "waiting for the veth link's carrier";
  }
  ~TwoHosts() {
    run(ip_ + " netns delete " + host_a_);  // deleting a namespace deletes its end of the veth pair
    run(ip_ + " netns delete " + host_b_);
  }
  TwoHosts(const TwoHosts&) = delete;
  TwoHosts& operator=(const TwoHosts&) = delete;

  /// The command that failed while setting up, or empty.
  const std::string& failure() const { return failure_; }
  /// argv running `program` inside host a or b.
  std::vector<std::string> in_a(std::vector<std::string> program) const { return in(host_a_, std::move(program)); }
  std::vector<std::string> in_b(std::vector<std::string> program) const { return in(host_b_, std::move(program)); }
  /// Bytes host b received on its veth end.
  std::uint64_t bytes_received_by_b() const {
    const auto text = run(ip_ + " netns exec " + host_b_ + " cat /sys/class/net/" + veth_b_ + "/statistics/rx_bytes");
    return text ? std::stoull(*text) : 0;
  }

 private:
  bool link_up(const std::string& host, const std::string& veth) const {
    return run(ip_ + " -n " + host + " link show dev " + veth).value_or("").find("state UP") != std::string::npos;
  }

  std::vector<std::string> in(const std::string& host, std::vector<std::string> program) const {
    std::vector<std::string> argv = {ip_, "netns", "exec", host};
    argv.insert(argv.end(), program.begin(), program.end());
    return argv;
  }

  std::string ip_;
  std::string host_a_, host_b_, veth_b_;
  std::string failure_;
};

/// Two hosts for each case, or the case skipped where namespaces cannot be made.
class DdsMultiHost : public ::testing::Test {
 protected:
  void SetUp() override {
    if (geteuid() != 0) GTEST_SKIP() << "creating network namespaces needs root; run this test as root (CI does)";
    const std::string ip = ip_program();
    if (ip.empty()) GTEST_SKIP() << "iproute2's `ip` is not installed (toolchain/install-deps.sh installs it)";
    remove_stale_namespaces(ip);
    hosts_.emplace(ip);
    ASSERT_TRUE(hosts_->failure().empty()) << "setting up the namespaces failed at: " << hosts_->failure();
  }

  std::optional<TwoHosts> hosts_;
};

/// A recording of 100 rounds, 20 ms apart, of the navview test scene (frame, needle,
/// prediction, surface).
void write_scene_recording(const std::string& path) {
  auto writer = RecordingWriter::create(path);
  ASSERT_TRUE(writer.ok());
  auto frame = scene_frame();
  NeedleState needle = scene_needle();
  TargetPrediction prediction = scene_prediction();
  auto surface = scene_surface();
  std::vector<std::uint8_t> bytes;
  const auto append = [&](auto& sample, TimeNs time_ns) {
    sample.source_time_ns = time_ns;
    ASSERT_TRUE(encode_sample(sample, bytes));
    ASSERT_TRUE(
        writer.value()->append(topic_of<std::remove_reference_t<decltype(sample)>>(), time_ns, time_ns, bytes).ok());
  };
  for (TimeNs round = 1; round <= 100; ++round) {
    const TimeNs time_ns = round * 20 * kNsPerMs;
    frame->sequence_number = static_cast<std::uint64_t>(round);
    dds::ToolPose probe = view::testing::probe_pose_placing_image_at_model(time_ns);
    append(probe, time_ns);
    append(*frame, time_ns);
    append(needle, time_ns);
    append(prediction, time_ns);
    append(*surface, time_ns);
  }
  ASSERT_TRUE(writer.value()->close().ok());
}

/// The demo scene on `local_address` with `peer` as its other host (its URDF by absolute path), in a file.
std::string demo_scene_on(const std::string& local_address, const std::string& peer, const std::string& path) {
  const std::string text =
      nav::testing::movable_demo_text() + "network:\n  local_address: " + local_address + "\n  peers: [" + peer + "]\n";
  std::ofstream(path) << text;
  return path;
}

TEST_F(DdsMultiHost, NavviewOnOneHostShowsWhatNavtoolReplaysOnAnother) {
  const TwoHosts& hosts = *hosts_;

  const std::string base = ::testing::TempDir() + "nav_multi_host_" + std::to_string(getpid());
  const std::filesystem::path out_dir = base + "_png";
  std::filesystem::remove_all(out_dir);
  write_scene_recording(base + ".navrec");
  write_scene_triangles_obj(base + "_square.obj");
  const std::uint64_t received_before = hosts.bytes_received_by_b();

  ChildProcess navview(hosts.in_b({std::string(NAV_BIN_DIR) + "/navview",
                                   "--headless",
                                   "--out-dir",
                                   out_dir.string(),
                                   "--period-ms",
                                   "50",
                                   "--duration-s",
                                   "120",
                                   "--surface-mesh",
                                   base + "_square.obj",
                                   "--unit",
                                   "mm",
                                   "--panel-height",
                                   std::to_string(kPanelHeightPx),
                                   "--azimuth-deg",
                                   "0",
                                   "--elevation-deg",
                                   "0",
                                   "--scene",
                                   demo_scene_on(kAddressB, kAddressA, base + "_navview.yaml"),
                                   "--domain",
                                   "165"}),
                       base + "_navview.log");
  ChildProcess player(
      hosts.in_a({std::string(NAV_BIN_DIR) + "/navtool", "replay", base + ".navrec", "--wait-for-readers-s", "30",
                  "--domain", "165", "--local-address", kAddressA, "--peer", kAddressB}),
      base + "_replay.log");
  EXPECT_EQ(player.wait(std::chrono::seconds(120)), 0) << player.log();
  std::string matching_png;
  EXPECT_TRUE(testing::wait_until(
      [&] {
        for (const std::string& png : png_files(out_dir)) {
          auto image = view::read_png(png);
          if (image.ok() && shows_scene(image.value())) matching_png = png;
        }
        return !matching_png.empty();
      },
      std::chrono::seconds(10)))
      << png_files(out_dir).size() << " PNG files, none shows the scene\n"
      << navview.log();
  navview.signal(SIGTERM);
  EXPECT_EQ(navview.wait(std::chrono::seconds(30)), 0) << navview.log();

  // The frames (48 kB each) travelled over the veth link, not through shared memory.
  const std::uint64_t received = hosts.bytes_received_by_b() - received_before;
  std::printf("host b received %llu bytes over veth\n", static_cast<unsigned long long>(received));
  EXPECT_GT(received, 50u * 240u * 200u);
  if (!HasFailure()) std::filesystem::remove_all(out_dir);
}

TEST_F(DdsMultiHost, AnEvaluationOnOneHostSeesALiveStationAndItsPatientOnAnother) {
  const TwoHosts& hosts = *hosts_;
  const std::string base = ::testing::TempDir() + "nav_multi_host_live_" + std::to_string(getpid());
  const std::string scene_a = demo_scene_on(kAddressA, kAddressB, base + "_a.yaml");
  const std::string scene_b = demo_scene_on(kAddressB, kAddressA, base + "_b.yaml");
  const std::string bin = NAV_BIN_DIR;
  const std::uint64_t received_before = hosts.bytes_received_by_b();

  ChildProcess patient(hosts.in_a({bin + "/navdevice", "sim", "--scene", scene_a, "--seconds", "6", "--domain", "166"}),
                       base + "_patient.log");
  ASSERT_TRUE(
      testing::wait_until([&] { return patient.log().find("waiting up to") != std::string::npos || patient.ended(); },
                          std::chrono::seconds(300)))
      << patient.log();
  ChildProcess evaluation(
      hosts.in_b({bin + "/navtool", "evaluate", "--scene", scene_b, "--seconds", "14", "--domain", "166"}),
      base + "_evaluate.log");
  ChildProcess station(
      hosts.in_a({bin + "/navstation", "--scene", scene_a, "--live", "--seconds", "7", "--domain", "166"}),
      base + "_station.log");
  const std::optional<int> station_exit = station.wait(std::chrono::seconds(120));
  const std::optional<int> patient_exit = patient.wait(std::chrono::seconds(60));
  const std::optional<int> evaluation_exit = evaluation.wait(std::chrono::seconds(60));
  std::printf("%s\n%s\n%s", station.log().c_str(), patient.log().c_str(), evaluation.log().c_str());
  ASSERT_EQ(station_exit, 0);
  ASSERT_EQ(patient_exit, 0);
  ASSERT_EQ(evaluation_exit, 0);
  // The station's predictions and the patient's truth crossed to host b, and compare as on one host.
  EXPECT_GE(nav::testing::number_after(evaluation.log(), "mm  ("), 300.0);
  EXPECT_LE(nav::testing::number_after(evaluation.log(), "tumour now "), 1.5);
  const std::uint64_t received = hosts.bytes_received_by_b() - received_before;
  std::printf("host b received %llu bytes over veth\n", static_cast<unsigned long long>(received));
  EXPECT_GT(received, 565u * 12u * 100u);  // at least 100 deformed surfaces of 565 vertices
}

}  // namespace
}  // namespace nav::dds
