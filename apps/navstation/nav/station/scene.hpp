#pragma once
// The station scene: one YAML file that declares what a navigation station runs (rates and
// cores, the URDF of its frames, the liver and its model rung, the optional needle and
// ligaments, its devices and DDS topics), parsed into plain structs. Paths in the file are
// relative to the file's own folder. Init-time code: it allocates and never throws; every
// error names the file, the line and the key path (e.g. `liver.model.rung`).
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "nav/connective/organ_ligaments.hpp"
#include "nav/core/error.hpp"
#include "nav/core/units.hpp"
#include "nav/fusion/rigid_pose.hpp"
#include "nav/needle/needle_parameters.hpp"
#include "nav/needle/needle_tissue_scene.hpp"
#include "nav/reduced/reduced_ladder.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/tissue/elastic_material.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav::station {

/// Scene files larger than this are refused before parsing.
inline constexpr std::size_t kMaxSceneBytes = 1u << 20;

/// `station:` rates, latency and the two cores of the station's threads.
struct StationSettings {
  std::string name;
  double loop_rate_hz = 1000.0;      ///< the real-time loop (needle and forces), at most 1 kHz
  double tissue_rate_hz = 100.0;     ///< the tissue step; divides loop_rate_hz
  double display_latency_ms = 50.0;  ///< how far ahead predictions look
  int realtime_core = 1;             ///< core of the real-time loop
  int io_core = 0;                   ///< core of the I/O thread (DDS, drivers, images)
  int realtime_priority = 80;        ///< SCHED_FIFO priority asked for, 1..99
  int io_priority = 20;     ///< the I/O thread's SCHED_FIFO priority, below realtime_priority; 0: normal scheduling
  bool lock_memory = true;  ///< mlockall(MCL_CURRENT | MCL_FUTURE) at start
};

/// `frames:` the URDF of the station's rigid frames.
struct FrameSettings {
  std::string urdf_path;  ///< resolved against the scene's folder
  int line = 0;           ///< line of `frames:` in the scene file
};

/// Where the liver mesh comes from.
enum class LiverMeshSource { generated, file };

/// `liver.mesh:` the embedded default liver, or a tetrahedral mesh file.
struct LiverMeshSettings {
  LiverMeshSource source = LiverMeshSource::generated;
  std::string path;                     ///< file only, resolved against the scene's folder
  LengthUnit unit = LengthUnit::metre;  ///< file only
  double element_size_m = 0.012;        ///< generated only
};

/// The liver's rung on the model ladder.
enum class LiverRung { full, reduced };

/// One rung above the reduced liver's own: a reduced-basis artifact (`navtool reduce --extend`).
struct EscalationRung {
  std::string artifact_path;  ///< resolved against the scene's folder
  int line = 0;               ///< its line in the scene file
};

/// `liver.model.escalation:` the reduced liver as the bottom rung of an escalation ladder:
/// further artifacts of strictly growing basis size (checked when built), optionally the
/// full order on top, and how the ladder moves between its rungs (escalation_allowed false:
/// the indicator only raises its flag).
struct EscalationSettings {
  std::vector<EscalationRung> rungs;  ///< rungs 1, 2, ... (rung 0 is liver.model.artifact)
  bool full_order_on_top = false;
  ReducedLadderOptions options;
  int line = 0;  ///< line of `escalation:`
};

/// `liver:` mesh, material, model rung and the tumour (the navigation target).
struct LiverSettings {
  LiverMeshSettings mesh;
  ElasticMaterial material;
  LiverRung rung = LiverRung::full;
  /// Full order: law, rotation, integrator, solver (step_s comes from tissue_rate_hz).
  TissueSolverOptions full;
  /// Reduced: the artifact written by `navtool reduce` and the online solver settings.
  std::string reduced_artifact_path;
  ReducedSolverOptions reduced;
  /// Reduced only, when declared: the ladder the reduced liver escalates on.
  std::optional<EscalationSettings> escalation;
  /// The tumour's centre in the model frame (metres); optional on the generated liver,
  /// which places its own.
  std::optional<Point3> tumour_m;
  int line = 0;  ///< line of `liver:`
};

/// `needle:` the needle and what it meets (present only when the scene has a needle).
/// Where a needle layer's surface comes from in the liver mesh (station_needle_surfaces.hpp).
struct NeedleLayerSurface {
  std::int32_t region = -1;  ///< -1: the mesh's boundary (the capsule); else the boundary of the elements so tagged
  int line = 0;
};

struct NeedleSettings {
  NeedleParameters parameters;    ///< step_s comes from loop_rate_hz
  NeedleTissueScene interaction;  ///< its layers (planes until their surfaces are taken from the mesh) and settings
  std::vector<std::optional<NeedleLayerSurface>> layer_surfaces;  ///< per layer; none: its plane
  /// The loop's needle meets the full-order compliance its reduced liver misses between nodes
  /// this close (a full-order liver built at start-up for it; 0: the point compliance alone).
  double missing_compliance_radius_m = 0.0;
  /// The share of the needle's point force its node keeps in the full-order livers the needle
  /// meets (the missing compliance's source, a simulated patient); the rest spreads over the
  /// node's neighbours (TissueScene::point_force_own_share). 1: the node alone.
  double point_force_own_share = 1.0;
  int line = 0;
};

/// `ligaments:` blocks hanging the liver from the wall above it.
struct LigamentSettings {
  ElasticMaterial material{1e5, 0.45, 1100.0};
  double rayleigh_mass_per_s = 1.0;
  /// The exact banded factor by default: on ligament-sized blocks it costs less than 60 CG
  /// iterations; CG for blocks whose band is too wide.
  FrameSolver solver = FrameSolver::banded_cholesky;
  std::vector<LigamentSpec> blocks;
  int line = 0;
};

/// The kinds of tracker a station can read.
enum class TrackerKind { simulated, ndi, apriltag };

/// `devices.tracker.tools:` which tool id on nav/tool_pose is which tracked tool (each its own).
struct ToolIds {
  std::uint32_t needle = 1;       ///< the needle's marker
  std::uint32_t probe = 2;        ///< the ultrasound probe's marker
  std::uint32_t respiratory = 3;  ///< the respiratory marker on the patient's skin
  /// The reference marker fixed to the patient, which the URDF's `reference_marker ->
  /// liver_model` registers the model to; without one the tracker itself is fixed to the patient.
  std::optional<std::uint32_t> reference;
};

/// One tag of a tool tracked by several AprilTags: its tag36h11 id and where it sits on the
/// tool (tool_from_tag).
struct ToolTag {
  int id = 0;
  RigidPose tool_from_tag;
};

/// `devices.tracker:` one of the three kinds with its settings.
struct TrackerSettings {
  TrackerKind kind = TrackerKind::simulated;
  // every kind: where and how fast a tool can plausibly be (dds::PoseBounds)
  double volume_radius_m = 3.0;    ///< of the tracker's measurement volume, around its origin
  double max_speed_m_per_s = 2.0;  ///< of any tracked tool
  /// every kind: the loop extrapolates a tool's pose over the tracker's latency along the
  /// least-squares velocity of its samples within this window (0: of its last two samples)
  double fit_window_ms = 100.0;
  ToolIds tools;          ///< every kind: the tools' ids on nav/tool_pose
  double rate_hz = 60.0;  ///< simulated: its sample rate; ndi: how often it is polled; apriltag: a file's pace
  // simulated
  double latency_ms = 0.0;
  double position_noise_m = 0.0;
  double rotation_noise_rad = 0.0;
  double dropout_probability = 0.0;
  std::uint64_t seed = 1;
  /// simulated: where the tracker sees the reference marker (tracker_from_reference; without a
  /// reference tool, the model's registration is the URDF's alone)
  RigidPose tracker_from_reference;
  // ndi: a serial device, or host and port; which port handle is which tool
  std::string serial_device;
  std::string host;
  int port = 0;
  ToolIds port_handles;
  int baud = 115200;  ///< a serial line's rate after COMM (9600 ... 921600)
  /// Passive tools by role (needle, probe, respiratory, reference): their .rom definition files,
  /// loaded into the device (PHRQ, PVWR), which gives their port handles (not port_handles).
  std::map<std::string, std::string> rom_files;
  // apriltag: the camera (a device index, /dev/videoN, a video or an image-sequence pattern),
  // the printed tags' edge, the camera's intrinsics (the file navtool calib camera writes;
  // required to track) and which tag36h11 id is which tool (the tool's frame at its tag)
  std::string camera_device;
  double tag_size_m = 0.0;
  std::string camera_intrinsics_path;
  ToolIds tag_ids{0, 1, 2, std::nullopt};
  /// apriltag: the tools tracked by several tags (a rigid body), by role, in place of their one
  /// tag in tag_ids
  std::map<std::string, std::vector<ToolTag>> tag_bodies;
};

/// One tracked tool by its role: its name, its frame in the URDF, its id on nav/tool_pose and
/// the device's own id for it (an NDI port handle, a tag id).
struct ToolRole {
  const char* role;
  const char* frame;
  std::uint32_t tool_id;
  std::uint32_t device_id;
};

/// The roles of `tools` with a device's ids for the same roles: needle, probe, respiratory,
/// and the reference when both declare one.
std::vector<ToolRole> tool_roles(const ToolIds& tools, const ToolIds& device_ids);

/// The tool id `tools` gives `role` (needle, probe, respiratory, or reference when declared), or nothing.
std::optional<std::uint32_t> tool_id_of_role(const ToolIds& tools, const std::string& role);

/// Whether a capture source names a device by its index ("0" for /dev/video0) rather than a file.
bool is_device_index(const std::string& source);

/// The kinds of ultrasound source.
enum class UltrasoundKind { simulated, plus, capture };

/// `devices.ultrasound:` a synthetic B-mode scanner, a PLUS recording played back, or a
/// frame grabber, video or image sequence read through OpenCV's capture.
struct UltrasoundSettings {
  UltrasoundKind kind = UltrasoundKind::simulated;
  double rate_hz = 20.0;        ///< simulated; capture: the pace of a file or sequence (a grabber keeps its own)
  double target_noise_m = 0.0;  ///< simulated: the filter's noise of the tumour point found in the frames
  std::uint64_t seed = 1;       ///< simulated
  std::string recording_path;   ///< plus, resolved against the scene's folder
  /// plus: the image's pixel spacing when the recording's is not it (a PLUS recording of a
  /// tracked probe says 1 x 1 and keeps the spacing in its probe calibration: the spacing
  /// navtool calib probe prints); without it, the recording's own
  std::optional<std::array<double, 2>> recording_pixel_spacing_m;
  /// capture: a device index ("0": /dev/video0), a video file or an image-sequence pattern
  /// ("frames/%04d.png", resolved against the scene's folder), the rectangle of the grabbed
  /// image that holds the ultrasound image (x, y, width, height in pixels; 0 x 0: all) and
  /// its pixel spacing along a row and a column.
  std::string capture_source;
  std::array<std::uint32_t, 4> clip_px{0, 0, 0, 0};
  std::array<double, 2> pixel_spacing_m{0.3e-3, 0.3e-3};
};

/// `devices:`
/// `devices.clock:` how the devices' stamps relate to this host's monotonic clock, and how
/// far a stamp may lie from its sample's arrival before the station refuses the sample.
struct DeviceClockSettings {
  double offset_ms = 0.0;              ///< added to a device's stamp to put it on this host's monotonic clock
  double max_ahead_ms = 50.0;          ///< a stamp this much later than its arrival is refused
  double max_behind_ms = 1000.0;       ///< a stamp this much earlier than its arrival is refused
  double bad_sample_hold_ms = 2000.0;  ///< a refused sample keeps bad_sample raised on the station's health this long
};

struct DeviceSettings {
  TrackerSettings tracker;
  UltrasoundSettings ultrasound;
  DeviceClockSettings clock;
};

/// `topics:` DDS domain and topic names (defaults: the names of nav::dds::topic_name). The
/// station reads poses and images and writes predictions, surfaces, needle states and health;
/// navview, run beside it, reads them by the same names. A simulated patient (navdevice sim)
/// also publishes its truth, which only an evaluation reads.
struct TopicSettings {
  std::uint32_t domain_id = 0;
  std::string poses = "nav/tool_pose";
  std::string images = "nav/ultrasound_frame";
  std::string predictions = "nav/target_prediction";
  std::string surfaces = "nav/deformed_surface";
  std::string needle_states = "nav/needle_state";
  std::string needle_forces = "nav/needle_force";  ///< at the loop rate, for a haptic display or a robot
  std::string health = "nav/station_health";
  std::string ground_truth = "nav/ground_truth";
};

/// `security:` DDS Security for every participant of the scene (absent: off). A path may hold
/// `{role}`, which each process replaces with its own role (station, devices, display, tool):
/// one scene serves the station, its devices and its displays, each with its own identity and
/// permissions (`navtool security init` makes them). Relative paths are from the scene's folder.
struct SecuritySettings {
  std::string ca;           ///< the CA of identities and permissions
  std::string certificate;  ///< a participant's identity
  std::string private_key;  ///< its key
  std::string governance;   ///< the domain's rules, signed by the CA
  std::string permissions;  ///< what a participant may read and write, signed by the CA
  int line = 0;             ///< of the section (0 when absent)
};

/// `network:` where the station's DDS participants talk (and its devices' and displays', which
/// read the same scene): the one local address UDP binds to, and the other hosts' addresses
/// (unicast discovery). Loopback alone by default; never multicast, never another interface.
struct NetworkSettings {
  std::string local_address = "127.0.0.1";
  std::vector<std::string> peers;
  int line = 0;               ///< of the section (0 when absent)
  SecuritySettings security;  ///< the scene's `security:` section
};

/// A numeric IPv4 address and a TCP port ("127.0.0.1:18944" in a scene).
struct TcpAddress {
  std::string host = "127.0.0.1";
  int port = 0;
};

/// `openigtlink:` the OpenIGTLink bridge (navbridge igtl). In: a PlusServer's tracked tools
/// (TRANSFORM messages, their device names mapped to the scene's tools) and its ultrasound
/// (IMAGE), from a server the bridge connects to, or from a sender that connects to the
/// bridge. Out: the station's outputs to displays such as 3D Slicer's OpenIGTLinkIF, which
/// connect to the bridge.
struct OpenIgtlinkSettings {
  std::optional<TcpAddress> plus;  ///< where the tools and images come from (absent: out only)
  bool plus_connects = false;      ///< true: the bridge listens at `plus` and the sender connects
  /// TRANSFORM device name (or TDATA element name) -> role (needle, probe, respiratory,
  /// reference), one name a role; default StylusToTracker: needle, ProbeToTracker: probe
  std::map<std::string, std::string> transforms{{"StylusToTracker", "needle"}, {"ProbeToTracker", "probe"}};
  std::string image;                        ///< the IMAGE device taken as the ultrasound (empty: any)
  TcpAddress displays{"127.0.0.1", 18944};  ///< where displays connect
  int line = 0;                             ///< of the section
};

/// A whole scene file.
struct Scene {
  std::string source_path;  ///< the scene file as given
  StationSettings station;
  FrameSettings frames;
  LiverSettings liver;
  std::optional<NeedleSettings> needle;
  std::optional<LigamentSettings> ligaments;
  DeviceSettings devices;
  TopicSettings topics;
  NetworkSettings network;
  std::optional<OpenIgtlinkSettings> openigtlink;
};

/// Parses scene text; `path` names it in errors and anchors its relative paths.
Result<Scene> parse_scene(const std::string& text, const std::string& path);

/// Reads and parses the scene file at `path`.
Result<Scene> load_scene(const std::string& path);

}  // namespace nav::station
