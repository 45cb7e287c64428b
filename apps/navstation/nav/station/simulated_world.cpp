#include "nav/station/simulated_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <random>
#include <span>
#include <string>

#include <Eigen/Geometry>

#include "nav/needle/coupled_needle_step.hpp"
#include "nav/needle/tissue_coupling.hpp"
#include "nav/station/station_loop.hpp"
#include "nav/station/station_needle_surfaces.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav::station {

namespace {

TimeNs period_ns(double rate_hz) { return static_cast<TimeNs>(std::llround(1e9 / rate_hz)); }

/// The patient's needle points' compliance about their nodes: little beside the nodes' own
/// (millimetres per newton), enough to keep points a few millimetres apart on one node apart.
constexpr double kPatientLocalComplianceM_N = 5e-4;

/// The patient's full-order liver: the scene's model on the patient's (softer) material, the
/// needle's point forces spread as the scene's needle says.
Result<TetFemModel> patient_liver(const StationLiver& liver, const Scene& scene, const WorldOptions& options,
                                  TimeNs step_ns) {
  TissueScene patient = liver.scene;
  patient.default_material.youngs_modulus_pa *= options.truth_stiffness_factor;
  if (scene.needle) patient.point_force_own_share = scene.needle->point_force_own_share;
  TissueSolverOptions solver = scene.liver.full;
  solver.step_s = seconds_of(step_ns);
  auto model = make_tet_fem_model(liver.mesh, patient, solver);
  if (!model.ok())
    return Error{.message = model.error().describe(),
                 .file = scene.source_path,
                 .line = scene.liver.line,
                 .field = "liver.model"};
  return model;
}

/// The diaphragm's true displacement at tissue step i: the marker's motion times the gain, late.
TissueInputs diaphragm_inputs(const BreathingGeometry& breathing, const WorldOptions& options, TimeNs step_ns,
                              std::size_t i) {
  const TimeNs t = static_cast<TimeNs>(i) * step_ns - options.diaphragm_lag_ns;
  const Eigen::Vector3d d = options.diaphragm_gain * breathing.diaphragm_per_marker * marker_displacement_m(options, t);
  TissueInputs inputs;
  inputs.prescribed_displacement_m = {d[0], d[1], d[2]};
  return inputs;
}

Point3 tumour_of(const StationLiver& liver, std::span<const double> positions_m) {
  Point3 p{};
  for (std::size_t v = 0; v < 4; ++v) {
    const auto node = static_cast<std::size_t>(liver.tumour.nodes[v]);
    for (std::size_t c = 0; c < 3; ++c) p[c] += liver.tumour.weights[v] * positions_m[3 * node + c];
  }
  return p;
}

/// The patient's liver has run away when its tumour is not finite or this far from its rest.
constexpr double kRunawayDisplacementM = 0.1;

/// The true tumour `tumour` of tissue step i, appended, or an Error naming the liver's model
/// when the patient's simulation ran away there (never a world that publishes it as truth).
Status record_tumour(SimulatedWorld& world, const StationLiver& liver, const Scene& scene, const Point3& tumour,
                     std::size_t i) {
  double moved_m2 = 0.0;
  for (std::size_t c = 0; c < 3; ++c) moved_m2 += (tumour[c] - liver.tumour_m[c]) * (tumour[c] - liver.tumour_m[c]);
  if (!(std::sqrt(moved_m2) <= kRunawayDisplacementM)) {
    char message[160];
    std::snprintf(message, sizeof message,
                  "the simulated patient's liver ran away at %.2f s: its tumour is %.4g mm from rest",
                  seconds_of(static_cast<TimeNs>(i) * world.step_ns), 1e3 * std::sqrt(moved_m2));
    return Error{.message = message, .file = scene.source_path, .line = scene.liver.line, .field = "liver.model"};
  }
  world.tumour_truth_m.push_back(tumour);
  return Done{};
}

std::size_t truth_steps(const Scene& scene, const WorldOptions& options, TimeNs step_ns) {
  const TimeNs latency_ns = static_cast<TimeNs>(std::llround(scene.station.display_latency_ms * 1e6));
  return static_cast<std::size_t>((options.duration_ns + latency_ns) / step_ns + 2);
}

/// The true tumour of every tissue step: the full-order model of the patient's material
/// driven by the diaphragm's true motion (a scene without a needle).
Status tumour_truth(SimulatedWorld& world, const StationLiver& liver, const Scene& scene,
                    const BreathingGeometry& breathing, const WorldOptions& options) {
  auto patient = patient_liver(liver, scene, options, world.step_ns);
  if (!patient.ok()) return patient.error();
  auto data = make_tet_fem_data(patient.value());
  if (!data.ok())
    return Error{.message = data.error().describe(),
                 .file = scene.source_path,
                 .line = scene.liver.line,
                 .field = "liver.model"};
  const std::size_t steps = truth_steps(scene, options, world.step_ns);
  world.tumour_truth_m.reserve(steps);
  for (std::size_t i = 0; i < steps; ++i) {
    step(patient.value(), data.value(), diaphragm_inputs(breathing, options, world.step_ns, i));
    if (Status kept = record_tumour(world, liver, scene, tumour_of(liver, data.value().positions_m), i); !kept.ok())
      return kept;
  }
  return Done{};
}

/// The true tumour of every tissue step and the true (bent) needle tip of every loop tick:
/// the scene's needle coupled to the patient's full-order liver (tissue_coupling.hpp), its
/// base at the true needle marker pose, the tissue stepping every loop_rate/tissue_rate ticks
/// with the needle's point forces and the diaphragm.
Status needle_and_tumour_truth(SimulatedWorld& world, const StationLiver& liver, const Scene& scene,
                               const BreathingGeometry& breathing, const WorldOptions& options) {
  const NeedleSettings& needle = *scene.needle;
  auto patient = patient_liver(liver, scene, options, world.step_ns);
  if (!patient.ok()) return patient.error();
  const int every = static_cast<int>(std::lround(scene.station.loop_rate_hz / scene.station.tissue_rate_hz));
  const auto needle_error = [&](const Error& e) {
    return Error{.message = e.describe(), .file = scene.source_path, .line = needle.line, .field = "needle"};
  };
  // The patient's full-order liver answers for itself at the needle's nodes; a point keeps
  // only a small compliance about its node (the scene's is what a reduced liver misses).
  auto surfaces = station_needle_interaction(scene, liver.mesh, liver.tumour_m);
  if (!surfaces.ok()) return surfaces.error();
  NeedleTissueScene interaction = std::move(surfaces).value();
  interaction.point_compliance_m_per_n = kPatientLocalComplianceM_N;
  auto model =
      make_coupled_needle_model(needle.parameters, interaction, patient.value(), liver.scene.max_point_forces, every);
  if (!model.ok()) return needle_error(model.error());
  const RigidPose marker_from_base = needle_marker_from_base();
  auto data =
      make_coupled_needle_data(model.value(), to_needle_pose(compose(world.needle_marker_at(0), marker_from_base)));
  if (!data.ok()) return needle_error(data.error());
  CoupledNeedleData& d = data.value();  // it holds the patient's tissue state too
  const std::size_t steps = truth_steps(scene, options, world.step_ns);
  world.needle_step_ns = world.step_ns / every;
  world.tumour_truth_m.reserve(steps);
  world.needle_tip_truth_m.reserve(steps * static_cast<std::size_t>(every));
  const auto tip_node = static_cast<std::size_t>(needle.parameters.element_count);
  for (std::size_t i = 0; i < steps; ++i) {
    for (int k = 0; k < every; ++k) {
      const TimeNs t = static_cast<TimeNs>(i) * world.step_ns + k * world.needle_step_ns;
      NeedleInputs inputs;
      inputs.base = to_needle_pose(compose(world.needle_marker_at(t), marker_from_base));
      step_needle(model.value(), d, inputs);
      if (k == 0) {
        step_tissue(model.value(), d, diaphragm_inputs(breathing, options, world.step_ns, i));
        if (Status kept = record_tumour(world, liver, scene, tumour_of(liver, d.tissue.positions_m), i); !kept.ok())
          return kept;
        world.needle_peak_inverted_elements =
            std::max(world.needle_peak_inverted_elements, d.tissue.report.inverted_elements);
      }
      const std::span<const double> nodes = d.interaction.needle.positions_m;
      world.needle_tip_truth_m.push_back({nodes[3 * tip_node], nodes[3 * tip_node + 1], nodes[3 * tip_node + 2]});
      world.needle_peak_tip_force_n =
          std::max(world.needle_peak_tip_force_n, tip_force_n(model.value().interaction, d.interaction).norm());
    }
  }
  world.needle_punctures = d.interaction.report.punctures;
  return Done{};
}

/// A rotation by a small random rotation vector of `std_rad` per axis.
Eigen::Quaterniond rotation_noise(std::mt19937_64& rng, double std_rad) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector3d v{std_rad * unit(rng), std_rad * unit(rng), std_rad * unit(rng)};
  const double angle = v.norm();
  return angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, v / angle)) : Eigen::Quaterniond::Identity();
}

Eigen::Vector3d position_noise(std::mt19937_64& rng, double std_m) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const double x = unit(rng), y = unit(rng), z = unit(rng);
  return std_m * Eigen::Vector3d{x, y, z};
}

/// The tracker's frames: needle and probe markers and the respiratory marker.
void track(const SimulatedWorld& world, const Scene& scene, const BreathingGeometry& breathing,
           const WorldOptions& options, std::vector<DeviceSample>& out) {
  const TrackerSettings& tracker = scene.devices.tracker;
  std::mt19937_64 rng(tracker.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const TimeNs latency_ns = static_cast<TimeNs>(std::llround(tracker.latency_ms * 1e6));
  for (TimeNs t = 0; t <= options.duration_ns; t += period_ns(tracker.rate_hz)) {
    if (tracker.dropout_probability > 0.0 && uniform(rng) < tracker.dropout_probability) continue;
    DeviceSample needle{SampleKind::needle_pose, t, t + latency_ns, {}, Eigen::Vector3d::Zero()};
    const RigidPose marker = world.needle_marker_at(t);
    needle.pose = {marker.position_m + position_noise(rng, tracker.position_noise_m),
                   rotation_noise(rng, tracker.rotation_noise_rad) * marker.rotation};
    out.push_back(needle);
    DeviceSample probe{SampleKind::probe_pose, t, t + latency_ns, {}, Eigen::Vector3d::Zero()};
    const RigidPose probe_truth = world.probe_at(t);
    probe.pose = {probe_truth.position_m + position_noise(rng, tracker.position_noise_m),
                  rotation_noise(rng, tracker.rotation_noise_rad) * probe_truth.rotation};
    out.push_back(probe);
    DeviceSample marker_sample{SampleKind::respiratory, t, t + latency_ns, {}, Eigen::Vector3d::Zero()};
    marker_sample.point_m = breathing.marker_rest_m + Eigen::Vector3d{0.0, 0.0, marker_displacement_m(options, t)} +
                            position_noise(rng, tracker.position_noise_m);
    out.push_back(marker_sample);
  }
}

/// The scanner's frames: the probe's true image plane through the tissue around the true
/// tumour. The tissue near the tumour moves with it (a local translation by the tumour's
/// displacement from rest), so each frame images the rest-shape liver from the plane moved
/// back by that displacement.
void scan(SimulatedWorld& world, const StationLiver& liver, const Scene& scene, const WorldOptions& options) {
  const UltrasoundSettings& ultrasound = scene.devices.ultrasound;
  std::mt19937_64 rng(ultrasound.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  ultrasound::BmodeScene tissue = ultrasound::default_bmode_scene();
  tissue.tumour_centre_m = liver.tumour_m;
  ultrasound::BmodeSimulator simulator(world.imaging.geometry, tissue, ultrasound.seed);
  const Eigen::Vector3d rest{liver.tumour_m[0], liver.tumour_m[1], liver.tumour_m[2]};
  const std::size_t pixel_count = std::size_t{world.imaging.geometry.width_px} * world.imaging.geometry.height_px;
  for (TimeNs t = 0; t <= options.duration_ns; t += period_ns(ultrasound.rate_hz)) {
    if (options.ultrasound_frame_loss > 0.0 && uniform(rng) < options.ultrasound_frame_loss) continue;
    const RigidPose probe = world.probe_at(t);
    const Point3 tumour = world.tumour_at(t);
    const Eigen::Vector3d displacement = Eigen::Vector3d{tumour[0], tumour[1], tumour[2]} - rest;
    Eigen::Isometry3d rest_from_probe = Eigen::Isometry3d::Identity();
    rest_from_probe.linear() = probe.rotation.toRotationMatrix();
    rest_from_probe.translation() = probe.position_m - displacement;
    const Eigen::Isometry3d rest_from_image = rest_from_probe * world.imaging.probe_from_image;
    UltrasoundImage frame;
    frame.pixels.resize(pixel_count);
    frame.tumour_visible = simulator.render(rest_from_image, frame.pixels.data()).tumour_visible();
    DeviceSample seen{SampleKind::ultrasound_frame, t, t + options.ultrasound_delay_ns, {}, Eigen::Vector3d::Zero()};
    seen.frame_index = static_cast<std::int32_t>(world.frames.size());
    world.frames.push_back(std::move(frame));
    world.samples.push_back(seen);
  }
}

}  // namespace

Point3 SimulatedWorld::tumour_at(TimeNs time_ns) const {
  const TimeNs clamped = std::clamp<TimeNs>(time_ns, 0, static_cast<TimeNs>(tumour_truth_m.size() - 2) * step_ns);
  const auto i = static_cast<std::size_t>(clamped / step_ns);
  const double f = static_cast<double>(clamped % step_ns) / static_cast<double>(step_ns);
  Point3 p{};
  for (std::size_t c = 0; c < 3; ++c) p[c] = (1.0 - f) * tumour_truth_m[i][c] + f * tumour_truth_m[i + 1][c];
  return p;
}

Eigen::Vector3d SimulatedWorld::needle_tip_at(TimeNs time_ns) const {
  if (needle_tip_truth_m.empty())
    return needle_start_m + seconds_of(std::min(time_ns, needle_stop_ns)) * needle_velocity_m_s;
  const TimeNs clamped =
      std::clamp<TimeNs>(time_ns, 0, static_cast<TimeNs>(needle_tip_truth_m.size() - 1) * needle_step_ns);
  const Point3& p = needle_tip_truth_m[static_cast<std::size_t>(clamped / needle_step_ns)];
  return {p[0], p[1], p[2]};
}

RigidPose SimulatedWorld::needle_marker_at(TimeNs time_ns) const {
  const Eigen::Quaterniond rotation =
      Eigen::Quaterniond::FromTwoVectors(-Eigen::Vector3d::UnitZ(), needle_velocity_m_s.normalized());
  const Eigen::Vector3d tip = needle_start_m + seconds_of(std::min(time_ns, needle_stop_ns)) * needle_velocity_m_s;
  return {tip - rotation * Eigen::Vector3d{0.0, 0.0, -needle_length_m}, rotation};
}

RigidPose SimulatedWorld::probe_at(TimeNs time_ns) const {
  const double sweep_rad =
      probe_sweep_rad * std::sin(2.0 * std::numbers::pi * seconds_of(time_ns) / probe_sweep_period_s);
  return {probe_centre_m, Eigen::Quaterniond(Eigen::AngleAxisd(sweep_rad, Eigen::Vector3d::UnitX()))};
}

TimeNs world_period_ns(const WorldOptions& options) {
  const auto ms = [](double s) { return std::max<std::int64_t>(1, std::llround(1e3 * s)); };
  return std::lcm(ms(options.breathing_period_s), ms(options.probe_sweep_period_s)) * kNsPerMs;
}

double marker_displacement_m(const WorldOptions& options, TimeNs time_ns) {
  return options.marker_amplitude_m *
         std::sin(2.0 * std::numbers::pi * seconds_of(time_ns) / options.breathing_period_s);
}

Status check_simulated_devices(const Scene& scene) {
  if (scene.devices.tracker.kind == TrackerKind::simulated &&
      scene.devices.ultrasound.kind == UltrasoundKind::simulated)
    return Done{};
  return Error{.message =
                   "the simulated world plays simulated devices only (kind: simulated); this scene's devices are real: "
                   "run the station live "
                   "(navstation --live) with their device processes",
               .file = scene.source_path,
               .field = "devices"};
}

Result<SimulatedWorld> simulate_world(const StationLiver& liver, const Scene& scene, const BreathingGeometry& breathing,
                                      const WorldOptions& options) {
  if (const Status simulated = check_simulated_devices(scene); !simulated.ok()) return simulated.error();
  SimulatedWorld world;
  world.step_ns = period_ns(scene.station.tissue_rate_hz);
  world.duration_ns = options.duration_ns;
  const Eigen::Vector3d toward = -Eigen::Vector3d{0.0, 1.0, 0.25}.normalized();  // from in front, a little above
  world.needle_start_m = Eigen::Vector3d{liver.tumour_m[0], liver.tumour_m[1], liver.tumour_m[2]} -
                         options.needle_start_distance_m * toward;
  world.needle_velocity_m_s = options.needle_speed_m_s * toward;
  world.needle_stop_ns = static_cast<TimeNs>(std::llround(1e9 * options.needle_travel_m / options.needle_speed_m_s));
  world.needle_length_m = scene.needle ? scene.needle->parameters.length_m : 0.15;
  const Status truth = scene.needle ? needle_and_tumour_truth(world, liver, scene, breathing, options)
                                    : tumour_truth(world, liver, scene, breathing, options);
  if (!truth.ok()) return truth.error();
  auto imaging = scene_probe_imaging(scene);  // the patient's probe is the one the scene calibrated
  if (!imaging.ok()) return imaging.error();
  world.imaging = imaging.value();
  world.probe_centre_m =
      Eigen::Vector3d{liver.tumour_m[0], liver.tumour_m[1], liver.tumour_m[2] + options.probe_height_m};
  world.probe_sweep_rad = options.probe_sweep_rad;
  world.probe_sweep_period_s = options.probe_sweep_period_s;
  track(world, scene, breathing, options, world.samples);
  scan(world, liver, scene, options);
  std::stable_sort(world.samples.begin(), world.samples.end(),
                   [](const DeviceSample& a, const DeviceSample& b) { return a.delivered_ns < b.delivered_ns; });
  return world;
}

}  // namespace nav::station
