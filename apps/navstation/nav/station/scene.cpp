#include "nav/station/scene.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <new>
#include <utility>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/station/yaml_reader.hpp"

namespace nav::station {

namespace {

using detail::MapReader;
using detail::Range;

constexpr Range kPositive{0.0, 1e12, true};
constexpr Range kNonNegative{0.0, 1e12};
constexpr Range kFraction{0.0, 1.0};
constexpr int kIoPriority = 20;  // the I/O thread's SCHED_FIFO priority unless the scene says (below the loop's)
constexpr long long kMaxTag36h11Id = 586;  // the family has 587 codes

/// `path` relative to the scene file's folder (absolute paths are kept).
std::string resolve(const std::string& scene_path, const std::string& path) {
  const std::filesystem::path given(path);
  if (given.is_absolute()) return given.lexically_normal().string();
  return (std::filesystem::path(scene_path).parent_path() / given).lexically_normal().string();
}

/// Turns an Error of an rtlib validator, whose field is `prefix` + a key of `reader`'s map,
/// into a failure at that key.
void check(const Status& status, const MapReader& reader, const std::string& prefix) {
  if (status.ok()) return;
  const std::string& field = status.error().field;
  const std::string key = field.rfind(prefix, 0) == 0 ? field.substr(prefix.size()) : std::string();
  reader.fail_at(reader.has(key) ? key : std::string(), status.error().message);
}

StationSettings read_station(MapReader r) {
  StationSettings s;
  s.name = r.text("name");
  s.loop_rate_hz = r.number("loop_rate_hz", Range{0.0, 1000.0, true});
  s.tissue_rate_hz = r.number("tissue_rate_hz", Range{0.0, s.loop_rate_hz, true});
  const double ratio = s.loop_rate_hz / s.tissue_rate_hz;
  if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio)
    r.fail_at("tissue_rate_hz", "must divide loop_rate_hz a whole number of times");
  s.display_latency_ms = r.number("display_latency_ms", Range{0.0, 1000.0});
  MapReader cores = r.map("cores");
  s.realtime_core = static_cast<int>(cores.integer("realtime", 0, 1023));
  s.io_core = static_cast<int>(cores.integer("io", 0, 1023));
  if (s.realtime_core == s.io_core) cores.fail_at("io", "must differ from cores.realtime");
  cores.finish();
  s.realtime_priority = static_cast<int>(r.integer("realtime_priority", 1, 99, 80));
  s.io_priority = static_cast<int>(r.integer("io_priority", 0, 98, std::min(kIoPriority, s.realtime_priority - 1)));
  if (s.io_priority >= s.realtime_priority)
    r.fail_at("io_priority", "must be below realtime_priority (the loop preempts the I/O thread)");
  s.lock_memory = r.boolean("lock_memory", true);
  r.finish();
  return s;
}

ElasticMaterial read_material(MapReader r, ElasticMaterial fallback) {
  ElasticMaterial m;
  m.youngs_modulus_pa = r.number("youngs_modulus_pa", kPositive, fallback.youngs_modulus_pa);
  m.poisson_ratio = r.number("poisson_ratio", Range{-1.0, 0.4999}, fallback.poisson_ratio);
  m.density_kg_m3 = r.number("density_kg_m3", kPositive, fallback.density_kg_m3);
  r.finish();
  return m;
}

LiverMeshSettings read_mesh(MapReader& liver, const std::string& scene_path) {
  LiverMeshSettings mesh;
  const YAML::Node node = liver.required("mesh");
  if (node.IsScalar()) {
    if (node.Scalar() != "generated") liver.fail_at("mesh", "expected 'generated' or a map with 'path' and 'unit'");
    return mesh;
  }
  MapReader r(liver.file(), node, liver.path_of("mesh"), liver.mark());
  mesh.source = static_cast<LiverMeshSource>(r.choice("source", {"generated", "file"}));
  if (mesh.source == LiverMeshSource::file) {
    mesh.path = resolve(scene_path, r.text("path"));
    mesh.unit = static_cast<LengthUnit>(r.choice("unit", {"m", "cm", "mm"}));
  } else {
    mesh.element_size_m = r.number("element_size_m", Range{0.004, 0.05}, mesh.element_size_m);
  }
  r.finish();
  return mesh;
}

void read_full_order(MapReader& r, double tissue_rate_hz, TissueSolverOptions& o) {
  o.law = static_cast<ElementLaw>(r.choice("law", {"linear_elastic", "st_venant_kirchhoff"}));
  o.rotation = static_cast<ElementRotation>(r.choice("rotation", {"corotational", "none"}, 0));
  o.integrator = static_cast<Integrator>(
      r.choice("integrator", {"implicit_euler", "quasi_static", "explicit_central_difference"}));
  o.solver = static_cast<LinearSolver>(r.choice("solver", {"ldlt_warped", "cg_jacobi", "cg_block_jacobi"}, 0));
  o.cg_iterations = static_cast<int>(r.integer("cg_iterations", 1, 500, 3));
  o.incompressibility_gain_pa = r.number("incompressibility_gain_pa", kNonNegative, 0.0);
  o.rayleigh_mass_per_s = r.number("rayleigh_mass_per_s", kNonNegative, 0.0);
  o.rayleigh_stiffness_s = r.number("rayleigh_stiffness_s", kNonNegative, 0.0);
  o.step_s = 1.0 / tissue_rate_hz;
}

EscalationSettings read_escalation(MapReader r, const std::string& scene_path, double envelope_factor) {
  EscalationSettings e;
  e.line = r.line();
  const YAML::Node rungs = r.required("rungs");
  if (!rungs.IsSequence() || rungs.size() == 0 || rungs.size() > 8)
    r.fail_at("rungs", "expected a list of 1 to 8 reduced-basis artifacts (navtool reduce --extend)");
  for (std::size_t i = 0; i < rungs.size(); ++i) {
    const std::string path =
        detail::scalar_text(r.file(), rungs[i], r.mark(), r.path_of("rungs") + "[" + std::to_string(i) + "]");
    e.rungs.push_back({resolve(scene_path, path), rungs[i].Mark().is_null() ? e.line : rungs[i].Mark().line + 1});
  }
  e.full_order_on_top = r.boolean("full_order_on_top", false);
  ReducedLadderOptions& o = e.options;
  o.escalation_allowed = r.boolean("allowed", o.escalation_allowed);
  o.escalate_after_steps = static_cast<int>(r.integer("escalate_after_steps", 1, 1000000, o.escalate_after_steps));
  o.de_escalate_after_steps =
      static_cast<int>(r.integer("de_escalate_after_steps", 0, 1000000, o.de_escalate_after_steps));
  o.de_escalation_envelope_ratio =
      r.number("de_escalation_envelope_ratio", Range{0.0, 100.0}, o.de_escalation_envelope_ratio);
  if (o.de_escalate_after_steps > 0 && !(o.de_escalation_envelope_ratio < envelope_factor))
    r.fail_at("de_escalation_envelope_ratio",
              "must be below liver.model.envelope_factor, or the ladder would step down only to escalate again");
  o.de_escalation_residual = r.number("de_escalation_residual", kFraction, o.de_escalation_residual);
  r.finish();
  return e;
}

void read_reduced(MapReader& r, const std::string& scene_path, double tissue_rate_hz, LiverSettings& liver) {
  liver.reduced_artifact_path = resolve(scene_path, r.text("artifact"));
  ReducedSolverOptions& o = liver.reduced;
  o.integrator = static_cast<ReducedIntegrator>(r.choice("integrator", {"implicit_euler", "quasi_static"}, 0));
  o.newton_iterations = static_cast<int>(r.integer("newton_iterations", 1, 50, 1));
  o.frozen_tangent = r.boolean("frozen_tangent", true);
  o.rayleigh_mass_per_s = r.number("rayleigh_mass_per_s", kNonNegative, 0.0);
  o.rayleigh_stiffness_s = r.number("rayleigh_stiffness_s", kNonNegative, 0.0);
  o.envelope_factor = r.number("envelope_factor", Range{1.0, 100.0}, o.envelope_factor);
  o.error_bound_m = 1e-3 * r.number("error_bound_mm", Range{0.0, 1000.0, true}, 1e3 * o.error_bound_m);
  o.step_s = 1.0 / tissue_rate_hz;
  if (r.optional("escalation")) liver.escalation = read_escalation(r.map("escalation"), scene_path, o.envelope_factor);
}

LiverSettings read_liver(MapReader r, const std::string& scene_path, double tissue_rate_hz) {
  LiverSettings liver;
  liver.line = r.line();
  liver.mesh = read_mesh(r, scene_path);
  if (r.optional("material")) liver.material = read_material(r.map("material"), liver.material);
  MapReader model = r.map("model");
  liver.rung = static_cast<LiverRung>(model.choice("rung", {"full", "reduced"}));
  if (liver.rung == LiverRung::full) {
    read_full_order(model, tissue_rate_hz, liver.full);
  } else {
    read_reduced(model, scene_path, tissue_rate_hz, liver);
  }
  model.finish();
  if (r.optional("tumour_m")) liver.tumour_m = r.point("tumour_m");
  if (!liver.tumour_m && liver.mesh.source == LiverMeshSource::file)
    r.fail_at("tumour_m", "required with a mesh file (the tumour's centre in the model frame, metres)");
  r.finish();
  return liver;
}

/// One layer: a surface of the mesh (`surface: capsule | tumour`, or `region: N`, a tagged
/// region's boundary) or a plane (surface_point_m and outward_normal).
TissueLayer read_layer(MapReader r, std::optional<NeedleLayerSurface>& from_mesh) {
  TissueLayer layer;
  const bool named = r.has("surface"), tagged = r.has("region");
  if (named && tagged) r.fail_at("region", "a layer takes either surface or region, not both");
  if ((named || tagged) && (r.has("surface_point_m") || r.has("outward_normal")))
    r.fail_at(named ? "surface" : "region", "a surface of the mesh takes no surface_point_m or outward_normal");
  if (named) {
    from_mesh = NeedleLayerSurface{.line = r.line()};
    if (r.choice("surface", {"capsule", "tumour"}) == 1)
      from_mesh->region = static_cast<std::int32_t>(TissueRegion::tumour);
  } else if (tagged) {
    from_mesh =
        NeedleLayerSurface{.region = static_cast<std::int32_t>(r.integer("region", 0, 1 << 30)), .line = r.line()};
  } else {
    layer.surface_point_m = r.point("surface_point_m");
    layer.outward_normal = r.point("outward_normal");
    const Point3& n = layer.outward_normal;
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(length > 1e-9)) r.fail_at("outward_normal", "must not be zero");
    for (double& v : layer.outward_normal) v /= length;
  }
  layer.puncture_force_n = r.number("puncture_force_n", kPositive, layer.puncture_force_n);
  layer.cutting_force_n = r.number("cutting_force_n", kNonNegative, layer.cutting_force_n);
  layer.friction_per_length_n_m = r.number("friction_per_length_n_m", kNonNegative, layer.friction_per_length_n_m);
  layer.surface_friction_coefficient =
      r.number("surface_friction_coefficient", kNonNegative, layer.surface_friction_coefficient);
  r.finish();
  return layer;
}

NeedleSettings read_needle(MapReader r, double loop_rate_hz) {
  NeedleSettings needle;
  needle.line = r.line();
  NeedleParameters& p = needle.parameters;
  p.length_m = r.number("length_m", Range{0.0, 1.0, true}, p.length_m);
  p.outer_diameter_m = r.number("outer_diameter_m", Range{0.0, 0.01, true}, p.outer_diameter_m);
  p.inner_diameter_m = r.number("inner_diameter_m", Range{0.0, 0.01}, p.inner_diameter_m);
  p.youngs_modulus_pa = r.number("youngs_modulus_pa", kPositive, p.youngs_modulus_pa);
  p.poisson_ratio = r.number("poisson_ratio", Range{-1.0, 0.4999}, p.poisson_ratio);
  p.density_kg_m3 = r.number("density_kg_m3", kPositive, p.density_kg_m3);
  p.bevel_angle_rad = r.number("bevel_angle_rad", Range{0.0, 1.5708, true}, p.bevel_angle_rad);
  p.theory = static_cast<BeamTheory>(r.choice("theory", {"euler_bernoulli", "timoshenko"}, 1));
  p.element_count = static_cast<int>(r.integer("element_count", 1, 200, p.element_count));
  p.integrator = static_cast<NeedleIntegrator>(r.choice("integrator", {"implicit_euler", "quasi_static"}, 0));
  p.newton_iterations = static_cast<int>(r.integer("newton_iterations", 1, 20, p.newton_iterations));
  p.max_pose_jump_m = r.number("max_pose_jump_m", kPositive, p.max_pose_jump_m);
  p.step_s = 1.0 / loop_rate_hz;
  check(validate_needle_parameters(p), r, "needle.");
  NeedleTissueScene& s = needle.interaction;
  if (r.optional("layers")) {
    const YAML::Node layers = r.required("layers");
    if (!layers.IsSequence()) r.fail_at("layers", "expected a list of layers");
    if (layers.size() > 16) r.fail_at("layers", "at most 16 layers");
    for (std::size_t i = 0; i < layers.size(); ++i) {
      std::optional<NeedleLayerSurface> from_mesh;
      s.layers.push_back(read_layer(
          MapReader(r.file(), layers[i], r.path_of("layers") + "[" + std::to_string(i) + "]", r.mark()), from_mesh));
      needle.layer_surfaces.push_back(from_mesh);
    }
  }
  s.point_compliance_m_per_n = r.number("point_compliance_m_per_n", kPositive, s.point_compliance_m_per_n);
  needle.missing_compliance_radius_m =
      r.number("missing_compliance_radius_m", Range{0.0, 0.1}, needle.missing_compliance_radius_m);
  needle.point_force_own_share = r.number("point_force_own_share", Range{0.0, 1.0, true}, needle.point_force_own_share);
  s.max_path_points = static_cast<int>(r.integer("max_path_points", 0, 256, s.max_path_points));
  s.gauss_seidel_sweeps = static_cast<int>(r.integer("gauss_seidel_sweeps", 1, 1000, s.gauss_seidel_sweeps));
  s.bevel_steering = r.boolean("bevel_steering", s.bevel_steering);
  r.finish();
  return needle;
}

LigamentSpec read_block(MapReader r) {
  LigamentSpec b;
  const std::vector<double> centre = r.numbers("footprint_centre_m", 2, Range{-1.0, 1.0});
  b.footprint_centre_m = {centre[0], centre[1], 0.0};
  b.width_m = r.number("width_m", Range{0.0, 0.2, true}, b.width_m);
  b.depth_m = r.number("depth_m", Range{0.0, 0.2, true}, b.depth_m);
  b.length_m = r.number("length_m", Range{0.0, 0.2, true}, b.length_m);
  if (r.optional("frames")) {
    const std::vector<double> frames = r.numbers("frames", 3, Range{2.0, 12.0});
    for (std::size_t i = 0; i < 3; ++i) {
      if (frames[i] != std::floor(frames[i])) r.fail_at("frames", "expected whole numbers of frames");
      b.frames[i] = static_cast<int>(frames[i]);
    }
  }
  b.embed_m = r.number("embed_m", Range{0.0, 0.05, true}, b.embed_m);
  r.finish();
  return b;
}

LigamentSettings read_ligaments(MapReader r) {
  LigamentSettings l;
  l.line = r.line();
  if (r.optional("material")) l.material = read_material(r.map("material"), l.material);
  l.rayleigh_mass_per_s = r.number("rayleigh_mass_per_s", kNonNegative, l.rayleigh_mass_per_s);
  l.solver = static_cast<FrameSolver>(r.choice("solver", {"banded_cholesky", "cg_block_jacobi"}, 0));
  const YAML::Node blocks = r.required("blocks");
  if (!blocks.IsSequence() || blocks.size() == 0 || blocks.size() > 8)
    r.fail_at("blocks", "expected a list of 1 to 8 ligament blocks");
  for (std::size_t i = 0; i < blocks.size(); ++i)
    l.blocks.push_back(
        read_block(MapReader(r.file(), blocks[i], r.path_of("blocks") + "[" + std::to_string(i) + "]", r.mark())));
  r.finish();
  return l;
}

/// The serial rates of an NDI device's COMM that a Linux host can set.
constexpr int kNdiSerialBauds[] = {9600, 19200, 38400, 57600, 115200, 230400, 921600};

/// `{needle: N, probe: N, respiratory: N, reference: N}`, each in [min, max] and distinct,
/// missing ones from `defaults` (reference: none unless given).
ToolIds read_tool_roles(MapReader roles, long long min, long long max, ToolIds defaults) {
  ToolIds ids;
  ids.needle = static_cast<std::uint32_t>(roles.integer("needle", min, max, defaults.needle));
  ids.probe = static_cast<std::uint32_t>(roles.integer("probe", min, max, defaults.probe));
  ids.respiratory = static_cast<std::uint32_t>(roles.integer("respiratory", min, max, defaults.respiratory));
  if (roles.optional("reference")) ids.reference = static_cast<std::uint32_t>(roles.integer("reference", min, max));
  const bool shared = ids.needle == ids.probe || ids.needle == ids.respiratory || ids.probe == ids.respiratory ||
                      (ids.reference && (*ids.reference == ids.needle || *ids.reference == ids.probe ||
                                         *ids.reference == ids.respiratory));
  if (shared) roles.fail_at("", "needle, probe, respiratory and reference need an id each");
  roles.finish();
  return ids;
}

/// `{xyz: [x, y, z], rpy: [roll, pitch, yaw]}`: a rigid pose in metres and URDF angles (radians).
RigidPose read_pose(MapReader r) {
  const Point3 xyz = r.point("xyz");
  const std::vector<double> rpy = r.numbers("rpy", 3, Range{-10.0, 10.0});
  r.finish();
  return {Eigen::Vector3d(xyz[0], xyz[1], xyz[2]),
          Eigen::Quaterniond(calibration::rpy_to_rotation(Eigen::Vector3d(rpy[0], rpy[1], rpy[2]))).normalized()};
}

constexpr std::size_t kMaxBodyTags = 8;

/// `bodies: {role: [{id: N, xyz: [...], rpy: [...]}, ...]}`: tools tracked by several tags,
/// each tag's pose on its tool.
std::map<std::string, std::vector<ToolTag>> read_tag_bodies(MapReader r, const ToolIds& tools) {
  std::map<std::string, std::vector<ToolTag>> bodies;
  for (const char* role : {"needle", "probe", "respiratory", "reference"}) {
    if (!r.optional(role)) continue;
    if (std::string(role) == "reference" && !tools.reference)
      r.fail_at(role, "no reference tool is declared in devices.tracker.tools");
    const YAML::Node list = r.required(role);
    if (!list.IsSequence() || list.size() == 0 || list.size() > kMaxBodyTags)
      r.fail_at(role, "expected a list of 1 to 8 tags, each {id: N, xyz: [x, y, z], rpy: [r, p, y]}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      MapReader tag(r.file(), list[i], r.path_of(role) + "[" + std::to_string(i) + "]", r.mark());
      const int id = static_cast<int>(tag.integer("id", 0, kMaxTag36h11Id));
      bodies[role].push_back({id, read_pose(tag)});
    }
  }
  r.finish();
  return bodies;
}

/// Fails unless every tag the tracker's tools use (a body's tags, or a tool's one tag) is on one tool.
void check_tags_distinct(MapReader& r, const TrackerSettings& t) {
  std::map<int, std::string> tool_of_tag;
  for (const ToolRole& role : tool_roles(t.tools, t.tag_ids)) {
    const auto body = t.tag_bodies.find(role.role);
    std::vector<int> ids{static_cast<int>(role.device_id)};
    if (body != t.tag_bodies.end()) {
      ids.clear();
      for (const ToolTag& tag : body->second) ids.push_back(tag.id);
    }
    for (const int id : ids) {
      const auto [where, added] = tool_of_tag.emplace(id, role.role);
      if (!added)
        r.fail_at(t.tag_bodies.empty() ? "tags" : "bodies",
                  "tag " + std::to_string(id) + " is on two tools (" + where->second + " and " + role.role + ")");
    }
  }
}

TrackerSettings read_tracker(MapReader r, const std::string& scene_path) {
  TrackerSettings t;
  t.kind = static_cast<TrackerKind>(r.choice("kind", {"simulated", "ndi", "apriltag"}));
  t.volume_radius_m = r.number("volume_radius_m", Range{0.0, 100.0, true}, t.volume_radius_m);
  t.max_speed_m_per_s = r.number("max_speed_m_per_s", Range{0.0, 100.0, true}, t.max_speed_m_per_s);
  t.fit_window_ms = r.number("fit_window_ms", Range{0.0, 1000.0}, t.fit_window_ms);
  if (r.optional("tools")) t.tools = read_tool_roles(r.map("tools"), 0, (1LL << 31) - 1, t.tools);
  switch (t.kind) {
    case TrackerKind::simulated:
      t.rate_hz = r.number("rate_hz", Range{0.0, 1000.0, true}, t.rate_hz);
      t.latency_ms = r.number("latency_ms", Range{0.0, 1000.0}, t.latency_ms);
      t.position_noise_m = r.number("position_noise_m", Range{0.0, 0.1}, t.position_noise_m);
      t.rotation_noise_rad = r.number("rotation_noise_rad", Range{0.0, 1.0}, t.rotation_noise_rad);
      t.dropout_probability = r.number("dropout_probability", kFraction, t.dropout_probability);
      t.seed = static_cast<std::uint64_t>(r.integer("seed", 0, 1LL << 62, 1));
      if (r.optional("tracker_from_reference")) {
        if (!t.tools.reference)
          r.fail_at("tracker_from_reference", "places the reference tool: declare it in tools (reference: ID)");
        t.tracker_from_reference = read_pose(r.map("tracker_from_reference"));
      }
      break;
    case TrackerKind::ndi:
      if (r.has("serial") == r.has("host")) r.fail_at("", "give either 'serial' (a device) or 'host' and 'port'");
      if (r.has("serial")) {
        t.serial_device = r.text("serial");
        t.baud = static_cast<int>(r.integer("baud", 9600, 921600, t.baud));
        if (std::find(std::begin(kNdiSerialBauds), std::end(kNdiSerialBauds), t.baud) == std::end(kNdiSerialBauds))
          r.fail_at("baud",
                    "an NDI device's rate (COMM) that this host can set: 9600, 19200, 38400, 57600, 115200, 230400 or "
                    "921600");
      } else {
        t.host = r.text("host");
        t.port = static_cast<int>(r.integer("port", 1, 65535));
      }
      t.rate_hz = r.number("rate_hz", Range{0.0, 1000.0, true}, t.rate_hz);
      if (r.optional("port_handles")) t.port_handles = read_tool_roles(r.map("port_handles"), 1, 255, t.port_handles);
      if (r.optional("rom_files")) {
        MapReader files = r.map("rom_files");
        for (const char* role : {"needle", "probe", "respiratory", "reference"})
          if (files.optional(role)) t.rom_files[role] = resolve(scene_path, files.text(role));
        files.finish();
      }
      break;
    case TrackerKind::apriltag: {
      const std::string camera = r.text("camera");
      t.camera_device = is_device_index(camera) || camera.rfind("/dev/", 0) == 0 ? camera : resolve(scene_path, camera);
      t.tag_size_m = r.number("tag_size_m", Range{0.0, 1.0, true});
      if (r.optional("intrinsics")) t.camera_intrinsics_path = resolve(scene_path, r.text("intrinsics"));
      if (r.optional("tags")) t.tag_ids = read_tool_roles(r.map("tags"), 0, kMaxTag36h11Id, t.tag_ids);
      if (r.optional("bodies")) t.tag_bodies = read_tag_bodies(r.map("bodies"), t.tools);
      // A reference on a body needs no tag of its own in tags to be one of the tracked tools.
      if (t.tag_bodies.count("reference") != 0 && !t.tag_ids.reference)
        t.tag_ids.reference = t.tag_bodies.at("reference").front().id;
      check_tags_distinct(r, t);
      t.rate_hz = r.number("rate_hz", Range{0.0, 1000.0, true}, t.rate_hz);
      break;
    }
  }
  r.finish();
  return t;
}

UltrasoundSettings read_ultrasound(MapReader r, const std::string& scene_path) {
  UltrasoundSettings u;
  u.kind = static_cast<UltrasoundKind>(r.choice("kind", {"simulated", "plus", "capture"}));
  if (u.kind == UltrasoundKind::simulated) {
    u.rate_hz = r.number("rate_hz", Range{0.0, 200.0, true}, u.rate_hz);
    u.target_noise_m = r.number("target_noise_m", Range{0.0, 0.1}, u.target_noise_m);
    u.seed = static_cast<std::uint64_t>(r.integer("seed", 0, 1LL << 62, 1));
  } else if (u.kind == UltrasoundKind::plus) {
    u.recording_path = resolve(scene_path, r.text("recording"));
    if (r.optional("pixel_spacing_mm")) {
      const std::vector<double> spacing = r.numbers("pixel_spacing_mm", 2, Range{0.0, 10.0, true});
      u.recording_pixel_spacing_m = std::array<double, 2>{1e-3 * spacing[0], 1e-3 * spacing[1]};
    }
  } else {
    const std::string source = r.text("source");
    u.capture_source = is_device_index(source) ? source : resolve(scene_path, source);
    u.rate_hz = r.number("rate_hz", Range{0.0, 200.0, true}, u.rate_hz);
    if (r.optional("clip_px")) {
      const std::vector<double> clip = r.numbers("clip_px", 4, Range{0.0, 65536.0});
      for (std::size_t i = 0; i < 4; ++i) {
        if (clip[i] != std::floor(clip[i])) r.fail_at("clip_px", "expected whole pixels: x, y, width, height");
        u.clip_px[i] = static_cast<std::uint32_t>(clip[i]);
      }
    }
    const std::vector<double> spacing = r.numbers("pixel_spacing_mm", 2, Range{0.0, 10.0, true});
    u.pixel_spacing_m = {1e-3 * spacing[0], 1e-3 * spacing[1]};
  }
  r.finish();
  return u;
}

DeviceClockSettings read_device_clock(MapReader r) {
  DeviceClockSettings c;
  constexpr double kDayMs = 86'400'000.0;
  c.offset_ms = r.number("offset_ms", Range{-1e3 * kDayMs, 1e3 * kDayMs}, c.offset_ms);
  c.max_ahead_ms = r.number("max_ahead_ms", Range{0.0, 10'000.0}, c.max_ahead_ms);
  c.max_behind_ms = r.number("max_behind_ms", Range{0.0, 60'000.0, true}, c.max_behind_ms);
  c.bad_sample_hold_ms = r.number("bad_sample_hold_ms", Range{0.0, 600'000.0, true}, c.bad_sample_hold_ms);
  r.finish();
  return c;
}

DeviceSettings read_devices(MapReader r, const std::string& scene_path) {
  DeviceSettings d;
  d.tracker = read_tracker(r.map("tracker"), scene_path);
  d.ultrasound = read_ultrasound(r.map("ultrasound"), scene_path);
  if (r.optional("clock")) d.clock = read_device_clock(r.map("clock"));
  r.finish();
  return d;
}

/// A DDS topic name: letters, digits, '_' and '/', not starting with '/' or a digit, and not
/// the name of a topic read before it (`taken`: name -> key).
std::string read_topic(MapReader& r, const std::string& key, const std::string& fallback,
                       std::map<std::string, std::string>& taken) {
  std::string name = r.text(key.c_str(), fallback.c_str());
  bool valid = name.size() <= 200 && name.front() != '/' && !(name.front() >= '0' && name.front() <= '9');
  for (char c : name)
    valid =
        valid && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '/');
  if (!valid) r.fail_at(key, "'" + name + "' is not a topic name (letters, digits, '_' and '/')");
  const auto [other, added] = taken.emplace(name, key);
  if (!added)
    r.fail_at(key,
              "'" + name + "' is already the name of topics." + other->second + " (every topic needs its own name)");
  return name;
}

TopicSettings read_topics(MapReader r) {
  TopicSettings t;
  std::map<std::string, std::string> taken;
  t.domain_id = static_cast<std::uint32_t>(r.integer("domain_id", 0, 232, 0));
  for (auto [key, name] : {std::pair{"poses", &t.poses},
                           {"images", &t.images},
                           {"predictions", &t.predictions},
                           {"surfaces", &t.surfaces},
                           {"needle_states", &t.needle_states},
                           {"needle_forces", &t.needle_forces},
                           {"health", &t.health},
                           {"ground_truth", &t.ground_truth}})
    *name = read_topic(r, key, *name, taken);
  r.finish();
  return t;
}

NetworkSettings read_network(MapReader r) {
  NetworkSettings n;
  n.line = r.line();
  n.local_address = r.text("local_address", n.local_address.c_str());
  if (r.optional("peers")) {
    const YAML::Node peers = r.required("peers");
    if (!peers.IsSequence()) r.fail_at("peers", "a list of the other hosts' IPv4 addresses, e.g. [10.0.0.2]");
    for (const YAML::Node& peer : peers) {
      if (!peer.IsScalar()) r.fail_at("peers", "a list of the other hosts' IPv4 addresses, e.g. [10.0.0.2]");
      n.peers.push_back(peer.as<std::string>());
    }
  }
  r.finish();
  return n;
}

/// "HOST:PORT": a numeric IPv4 address other than the wildcard, and a port 1..65535 (0 too
/// where the bridge listens: a free port, which it prints).
TcpAddress read_tcp_address(MapReader& r, const std::string& key, bool listening) {
  const std::string text = r.text(key);
  const std::size_t colon = text.rfind(':');
  TcpAddress address;
  in_addr parsed{};
  bool valid = colon != std::string::npos && colon + 1 < text.size() && colon < 16;
  if (valid) {
    address.host = text.substr(0, colon);
    const std::string port = text.substr(colon + 1);
    valid = port.size() <= 5 && port.find_first_not_of("0123456789") == std::string::npos &&
            inet_pton(AF_INET, address.host.c_str(), &parsed) == 1;
    address.port = valid ? std::stoi(port) : 0;
  }
  if (!valid || address.port < (listening ? 0 : 1) || address.port > 65535)
    r.fail_at(key, "'" + text + "' is not an IPv4 address and a port, e.g. 127.0.0.1:18944");
  if (parsed.s_addr == INADDR_ANY)
    r.fail_at(key, "0.0.0.0 is every interface: name the one address (127.0.0.1 for this host alone)");
  return address;
}

OpenIgtlinkSettings read_openigtlink(MapReader r, const ToolIds& tools) {
  OpenIgtlinkSettings o;
  o.line = r.line();
  if (r.optional("plus")) {
    MapReader plus = r.map("plus");
    if (plus.has("connect") == plus.has("listen"))
      plus.fail_at("", "give either 'connect' (a PlusServer's address) or 'listen' (where a sender connects)");
    o.plus_connects = plus.has("listen");
    o.plus = read_tcp_address(plus, o.plus_connects ? "listen" : "connect", o.plus_connects);
    plus.finish();
  }
  if (r.optional("transforms")) {
    MapReader names = r.map("transforms");
    o.transforms.clear();
    for (const auto& entry : r.required("transforms")) {
      const std::string device = detail::scalar_text(r.file(), entry.first, r.mark(), r.path_of("transforms"));
      const std::string role = names.text(device);
      if (device.empty() || device.size() > 20)
        names.fail_at(device, "an OpenIGTLink device name has 1 to 20 characters");
      if (!tool_id_of_role(tools, role))
        names.fail_at(device,
                      "unknown role '" + role +
                          "' (needle, probe, respiratory, or reference when devices.tracker.tools declares one)");
      for (const auto& [other, taken] : o.transforms)
        if (taken == role)  // two frames of one tool would alternate as its pose
          names.fail_at(device, "the role '" + role + "' is already " + other + "'s: one name a role");
      o.transforms[device] = role;
    }
    names.finish();
  }
  if (r.optional("image")) {
    o.image = r.text("image");
    if (o.image.size() > 20) r.fail_at("image", "an OpenIGTLink device name has 1 to 20 characters");
  }
  if (r.optional("displays")) o.displays = read_tcp_address(r, "displays", true);
  r.finish();
  return o;
}

SecuritySettings read_security(MapReader r, const std::string& scene_path) {
  SecuritySettings s;
  s.line = r.line();
  for (auto [key, path] : {std::pair{"ca", &s.ca},
                           {"certificate", &s.certificate},
                           {"private_key", &s.private_key},
                           {"governance", &s.governance},
                           {"permissions", &s.permissions}})
    *path = resolve(scene_path, r.text(key));
  r.finish();
  return s;
}

Scene read_scene(const YAML::Node& document, const std::string& path) {
  Scene scene;
  scene.source_path = path;
  MapReader root(path, document, "", YAML::Mark::null_mark());
  scene.station = read_station(root.map("station"));
  MapReader frames = root.map("frames");
  scene.frames.line = frames.line();
  scene.frames.urdf_path = resolve(path, frames.text("urdf"));
  frames.finish();
  scene.liver = read_liver(root.map("liver"), path, scene.station.tissue_rate_hz);
  if (root.optional("needle")) scene.needle = read_needle(root.map("needle"), scene.station.loop_rate_hz);
  if (root.optional("ligaments")) scene.ligaments = read_ligaments(root.map("ligaments"));
  scene.devices = read_devices(root.map("devices"), path);
  if (root.optional("topics")) scene.topics = read_topics(root.map("topics"));
  if (root.optional("network")) scene.network = read_network(root.map("network"));
  if (root.optional("security")) scene.network.security = read_security(root.map("security"), path);
  if (root.optional("openigtlink"))
    scene.openigtlink = read_openigtlink(root.map("openigtlink"), scene.devices.tracker.tools);
  root.finish();
  return scene;
}

}  // namespace

std::vector<ToolRole> tool_roles(const ToolIds& tools, const ToolIds& device_ids) {
  std::vector<ToolRole> roles{{"needle", "needle_marker", tools.needle, device_ids.needle},
                              {"probe", "probe_marker", tools.probe, device_ids.probe},
                              {"respiratory", "respiratory_marker", tools.respiratory, device_ids.respiratory}};
  if (tools.reference && device_ids.reference)
    roles.push_back({"reference", "reference_marker", *tools.reference, *device_ids.reference});
  return roles;
}

std::optional<std::uint32_t> tool_id_of_role(const ToolIds& tools, const std::string& role) {
  if (role == "needle") return tools.needle;
  if (role == "probe") return tools.probe;
  if (role == "respiratory") return tools.respiratory;
  if (role == "reference") return tools.reference;
  return std::nullopt;
}

bool is_device_index(const std::string& source) {
  return !source.empty() && source.find_first_not_of("0123456789") == std::string::npos;
}

Result<Scene> parse_scene(const std::string& text, const std::string& path) {
  if (text.size() > kMaxSceneBytes)
    return Error{.message = "larger than " + std::to_string(kMaxSceneBytes) + " bytes: not a scene file", .file = path};
  try {
    return read_scene(YAML::Load(text), path);
  } catch (const detail::SceneFailure& failure) {
    return failure.error;
  } catch (const YAML::Exception& e) {
    Error error{e.msg, path, e.mark.is_null() ? 0 : e.mark.line + 1, ""};
    if (!e.mark.is_null()) error.message += " (column " + std::to_string(e.mark.column + 1) + ")";
    return error;
  } catch (const std::bad_alloc&) {
    return Error{.message = "out of memory while parsing", .file = path};
  }
}

Result<Scene> load_scene(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{.message = "cannot open the scene file", .file = path};
  std::string text;
  text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  if (file.bad()) return Error{.message = "cannot read the scene file", .file = path};
  return parse_scene(text, path);
}

}  // namespace nav::station
