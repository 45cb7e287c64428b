#pragma once
// The simulated world of the demo station: the liver as ground truth, simulated by the
// full-order nonlinear model (corotational tetrahedra, implicit Euler, the scene's solver) at
// the tissue rate under a breathing diaphragm (which the respiratory marker only approximates:
// a gain and a lag the station's model does not know) and, with the scene's `needle:`, pushed,
// punctured and dragged by that needle (coupled to the full-order liver at the loop rate, its base
// at the true needle marker pose: tissue_coupling.hpp), and the devices that watch it: a tracker (the
// needle marker inserting the needle toward the tumour, the ultrasound probe sweeping over
// it, the respiratory marker) with the scene's rate, latency, noise and dropout, and a
// synthetic B-mode scanner on the tracked probe (BmodeSimulator: speckle, a hypoechoic tumour,
// vessels, capsule) imaging the tissue around the true, moving tumour at the scene's rate
// (frame loss optional); the station finds the tumour in those frames itself. The whole world is computed at start-up
// into a recording: every sample with the time it was measured and the time it reaches the station, in delivery order.
// Seeded RNGs only: the same scene and options give the same recording. Init-time code.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/fusion/rigid_pose.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_liver.hpp"
#include "nav/station/tumour_observer.hpp"

namespace nav::station {

/// What the world does beyond the scene's devices.
struct WorldOptions {
  TimeNs duration_ns = 10 * kNsPerSecond;
  double breathing_period_s = 4.0;
  double marker_amplitude_m = 0.005;    ///< the respiratory marker's amplitude (10 mm peak to peak)
  double truth_stiffness_factor = 0.7;  ///< the patient's tissue against the scene's (model's) material
  /// The true diaphragm moves this many times what the station's marker-to-diaphragm map
  /// says, and this long after the marker: the external marker is a surrogate of the motion inside.
  double diaphragm_gain = 1.3;
  TimeNs diaphragm_lag_ns = 200 * kNsPerMs;
  /// The needle holder's straight tip starts this far from the tumour, outside the liver (the
  /// needle comes from in front, a little above, along -(0, 1, 0.25): the generated liver's
  /// surface is 78.5 mm from the tumour on that path, below the diaphragm region), moves toward
  /// it and stops when it has travelled needle_travel_m (by default at the tumour's rest
  /// position, where a biopsy or an ablation holds it).
  double needle_start_distance_m = 0.083;
  double needle_speed_m_s = 0.005;
  double needle_travel_m = 0.083;
  double probe_sweep_rad = 0.3;  ///< the probe's sweep amplitude about the model x axis
  double probe_sweep_period_s = 3.0;
  double probe_height_m = 0.045;               ///< the probe marker above the tumour at rest (the image's depth to it)
  TimeNs ultrasound_delay_ns = 30 * kNsPerMs;  ///< from image capture to the frame at the station
  double ultrasound_frame_loss = 0.0;          ///< probability that a frame is lost
};

/// The kinds of recorded sample.
/// tumour: a tumour point in the model frame, as the station's image processing hands it to
/// the loop (the world records frames, never tumour points).
enum class SampleKind : std::uint8_t { needle_pose, probe_pose, respiratory, tumour, ultrasound_frame };

/// One sample of one simulated device (tracker frame = model frame).
struct DeviceSample {
  SampleKind kind = SampleKind::needle_pose;
  TimeNs measured_ns = 0;                             ///< when the device measured it
  TimeNs delivered_ns = 0;                            ///< when it reaches the station
  RigidPose pose;                                     ///< needle and probe markers
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();  ///< respiratory marker, or a tumour point
  std::int32_t frame_index = -1;                      ///< ultrasound_frame: the frame in SimulatedWorld::frames
};

/// One B-mode frame of the simulated scanner (row-major, the probe imaging's grid).
struct UltrasoundImage {
  std::vector<std::uint8_t> pixels;
  bool tumour_visible = false;  ///< the image plane cuts the tumour
};

/// The simulated world: the truth at every tissue step and the devices' recording.
struct SimulatedWorld {
  TimeNs step_ns = 10 * kNsPerMs;      ///< the tissue step
  TimeNs duration_ns = 0;              ///< the devices' samples cover [0, duration_ns]
  std::vector<Point3> tumour_truth_m;  ///< the true tumour at i * step_ns (full-order model)
  /// The needle holder's motion: where the straight needle's tip would be (the marker's
  /// tip point) at time 0, and its velocity; the marker at the needle's base, length_m back.
  Eigen::Vector3d needle_start_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d needle_velocity_m_s = Eigen::Vector3d::Zero();
  TimeNs needle_stop_ns = 0;  ///< when the holder stops (its tip at start + travel)
  double needle_length_m = 0.15;
  /// With the scene's needle: its true (bent) tip at k * needle_step_ns, from the needle
  /// coupled to the full-order liver; empty without a needle (the tip is then the straight one).
  std::vector<Point3> needle_tip_truth_m;
  TimeNs needle_step_ns = kNsPerMs;
  double needle_peak_tip_force_n = 0.0;   ///< the true needle's largest tip force over the run
  int needle_punctures = 0;               ///< surfaces the true needle punctured
  int needle_peak_inverted_elements = 0;  ///< most elements of the patient's liver inverted at once under the needle
  std::vector<DeviceSample> samples;      ///< in delivery order
  std::vector<UltrasoundImage> frames;    ///< the scanner's frames, by frame_index
  ProbeImaging imaging;                   ///< the scanner's grid and probe calibration
  Eigen::Vector3d probe_centre_m = Eigen::Vector3d::Zero();  ///< the probe marker's position
  double probe_sweep_rad = 0.0, probe_sweep_period_s = 1.0;
  /// The true tumour at any time within the run (linear between tissue steps).
  Point3 tumour_at(TimeNs time_ns) const;
  /// The true needle tip at any time (the bent tip of the coupled needle, if any).
  Eigen::Vector3d needle_tip_at(TimeNs time_ns) const;
  /// The true needle marker pose (model_from_marker) at any time: -z along the needle.
  RigidPose needle_marker_at(TimeNs time_ns) const;
  /// The true probe marker pose (model_from_probe) at any time.
  RigidPose probe_at(TimeNs time_ns) const;
};

/// The world's period once the needle has stopped: the shortest time holding whole breaths and
/// whole probe sweeps (12 s for 4 s breaths and 3 s sweeps, periods taken to the millisecond).
TimeNs world_period_ns(const WorldOptions& options);

/// The respiratory marker's true displacement along the tracker's z at time t (from its rest).
double marker_displacement_m(const WorldOptions& options, TimeNs time_ns);

/// Whether `scene`'s devices are the simulated ones (a tracker and a scanner of kind
/// `simulated`), which alone a simulated world can play; an Error naming `devices` otherwise.
Status check_simulated_devices(const Scene& scene);

/// Simulates the world of `scene` on `liver` for options.duration_ns (plus the display
/// latency, so that every prediction has its truth). Errors name the scene's section.
Result<SimulatedWorld> simulate_world(const StationLiver& liver, const Scene& scene, const BreathingGeometry& breathing,
                                      const WorldOptions& options);

}  // namespace nav::station
