#include "nav/station/simulated_world.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/Geometry>

#include "nav/tissue/tet_fem_model.hpp"

namespace nav::station {

namespace {

double seconds(TimeNs t) { return 1e-9 * static_cast<double>(t); }

TimeNs period_ns(double rate_hz) { return static_cast<TimeNs>(std::llround(1e9 / rate_hz)); }

/// The true tumour of every tissue step: the full-order model of the patient's material
/// driven by the diaphragm's true motion.
Result<std::vector<Point3>> tumour_truth(const StationLiver& liver, const Scene& scene, const BreathingGeometry& breathing,
                                         const WorldOptions& options, TimeNs step_ns) {
  TissueScene patient = liver.scene;
  patient.default_material.youngs_modulus_pa *= options.truth_stiffness_factor;
  TissueSolverOptions solver = scene.liver.full;
  solver.step_s = seconds(step_ns);
  auto model = make_tet_fem_model(liver.mesh, patient, solver);
  if (!model.ok()) return Error{model.error().describe(), scene.source_path, scene.liver.line, "liver.model"};
  auto data = make_tet_fem_data(model.value());
  if (!data.ok()) return Error{data.error().describe(), scene.source_path, scene.liver.line, "liver.model"};
  const TimeNs latency_ns = static_cast<TimeNs>(std::llround(scene.station.display_latency_ms * 1e6));
  const auto steps = static_cast<std::size_t>((options.duration_ns + latency_ns) / step_ns + 2);
  std::vector<Point3> truth;
  truth.reserve(steps);
  for (std::size_t i = 0; i < steps; ++i) {
    const TimeNs t = static_cast<TimeNs>(i) * step_ns - options.diaphragm_lag_ns;
    const Eigen::Vector3d d = options.diaphragm_gain * breathing.diaphragm_per_marker * marker_displacement_m(options, t);
    TissueInputs inputs;
    inputs.prescribed_displacement_m = {d[0], d[1], d[2]};
    step(model.value(), data.value(), inputs);
    Point3 p{};
    for (int v = 0; v < 4; ++v) {
      const auto node = static_cast<std::size_t>(liver.tumour.nodes[static_cast<std::size_t>(v)]);
      for (std::size_t c = 0; c < 3; ++c) p[c] += liver.tumour.weights[static_cast<std::size_t>(v)] * data.value().positions_m[3 * node + c];
    }
    truth.push_back(p);
  }
  return truth;
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
void track(const SimulatedWorld& world, const Scene& scene, const BreathingGeometry& breathing, const WorldOptions& options,
           std::vector<DeviceSample>& out) {
  const TrackerSettings& tracker = scene.devices.tracker;
  std::mt19937_64 rng(tracker.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const TimeNs latency_ns = static_cast<TimeNs>(std::llround(tracker.latency_ms * 1e6));
  const double needle_length_m = scene.needle ? scene.needle->parameters.length_m : 0.15;
  const Eigen::Quaterniond needle_rotation = Eigen::Quaterniond::FromTwoVectors(-Eigen::Vector3d::UnitZ(), world.needle_velocity_m_s.normalized());
  for (TimeNs t = 0; t <= options.duration_ns; t += period_ns(tracker.rate_hz)) {
    if (tracker.dropout_probability > 0.0 && uniform(rng) < tracker.dropout_probability) continue;
    DeviceSample needle{SampleKind::needle_pose, t, t + latency_ns, {}, Eigen::Vector3d::Zero()};
    const Eigen::Vector3d marker = world.needle_tip_at(t) - needle_rotation * Eigen::Vector3d{0.0, 0.0, -needle_length_m};
    needle.pose = {marker + position_noise(rng, tracker.position_noise_m), rotation_noise(rng, tracker.rotation_noise_rad) * needle_rotation};
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
    Eigen::Isometry3d probe_in_rest = Eigen::Isometry3d::Identity();
    probe_in_rest.linear() = probe.rotation.toRotationMatrix();
    probe_in_rest.translation() = probe.position_m - displacement;
    const Eigen::Isometry3d image_in_rest = probe_in_rest * world.imaging.image_to_probe;
    UltrasoundImage frame;
    frame.pixels.resize(pixel_count);
    frame.tumour_visible = simulator.render(image_in_rest, frame.pixels.data()).tumour_visible();
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

Eigen::Vector3d SimulatedWorld::needle_tip_at(TimeNs time_ns) const { return needle_start_m + seconds(time_ns) * needle_velocity_m_s; }

RigidPose SimulatedWorld::probe_at(TimeNs time_ns) const {
  const double sweep_rad = probe_sweep_rad * std::sin(2.0 * std::numbers::pi * seconds(time_ns) / probe_sweep_period_s);
  return {probe_centre_m, Eigen::Quaterniond(Eigen::AngleAxisd(sweep_rad, Eigen::Vector3d::UnitX()))};
}

double marker_displacement_m(const WorldOptions& options, TimeNs time_ns) {
  return options.marker_amplitude_m * std::sin(2.0 * std::numbers::pi * seconds(time_ns) / options.breathing_period_s);
}

Result<SimulatedWorld> simulate_world(const StationLiver& liver, const Scene& scene, const BreathingGeometry& breathing,
                                      const WorldOptions& options) {
  if (scene.devices.tracker.kind != TrackerKind::simulated || scene.devices.ultrasound.kind != UltrasoundKind::simulated)
    return Error{"the simulated world needs simulated devices", scene.source_path, 0, "devices"};
  SimulatedWorld world;
  world.step_ns = period_ns(scene.station.tissue_rate_hz);
  auto truth = tumour_truth(liver, scene, breathing, options, world.step_ns);
  if (!truth.ok()) return truth.error();
  world.tumour_truth_m = std::move(truth).value();
  const Eigen::Vector3d toward = -Eigen::Vector3d{0.0, 1.0, 1.0}.normalized();  // from above and in front
  world.needle_start_m = Eigen::Vector3d{liver.tumour_m[0], liver.tumour_m[1], liver.tumour_m[2]} - options.needle_start_distance_m * toward;
  world.needle_velocity_m_s = options.needle_speed_m_s * toward;
  world.imaging = demo_probe_imaging();
  world.probe_centre_m = Eigen::Vector3d{liver.tumour_m[0], liver.tumour_m[1], liver.tumour_m[2] + options.probe_height_m};
  world.probe_sweep_rad = options.probe_sweep_rad;
  world.probe_sweep_period_s = options.probe_sweep_period_s;
  track(world, scene, breathing, options, world.samples);
  scan(world, liver, scene, options);
  std::stable_sort(world.samples.begin(), world.samples.end(),
                   [](const DeviceSample& a, const DeviceSample& b) { return a.delivered_ns < b.delivered_ns; });
  return world;
}

}  // namespace nav::station
