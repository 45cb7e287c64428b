#pragma once
// The operating loop a running station steps, built from its scene's liver model: the reduced
// artifact of `liver.model.artifact`, the escalation ladder of `liver.model.escalation`, or,
// for a full-order rung, a reduced liver trained at start-up on the scene's full-order model
// (vibration modes, corotational cubature trained on quasi-static steps under diaphragm
// moves); the Kalman filter on the tumour on every rung; the scene's needle and ligaments.
// Init-time code.
#include <string>

#include "nav/core/error.hpp"
#include "nav/fusion/rigid_pose.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_liver.hpp"

namespace nav::station {

/// How the station's loop is built around its liver model.
struct StationLoopSettings {
  /// The reduced liver trained at start-up for a full-order rung.
  int basis_size = 16;                                  ///< vibration modes kept
  int max_cubature_samples = 32;                        ///< corotational cubature tetrahedra
  TimeNs needle_max_extrapolation_ns = 100 * kNsPerMs;  ///< display latency plus the tracker's delay
  /// The filter's correction: its standard deviation per mode as a fraction of the training
  /// envelope, and its correlation time. The start-up training moves the diaphragm only,
  /// which the lift carries; the modes' own envelope is small, and 3 times it lets the filter
  /// take up the demo's surrogate error (tumour RMS on a 6 s demo: 1.09 mm at 1 time, 0.77 mm
  /// at 3, 0.80 mm at 6, 0.99 mm at 10).
  double correction_fraction = 3.0;
  double correlation_time_s = 2.0;
  double gate_chi_square = 16.27;  ///< observations further from the prediction are rejected
};

/// The needle base (holder) in the needle marker's frame of the simulated needle (the demo
/// URDF's), marker_from_base: the needle points along the marker's -z from the marker's origin
/// (the tip straight at (0, 0, -length_m)), and along the base frame's +x, as the needle
/// models lie.
RigidPose needle_marker_from_base();

/// The tracked needle's calibration in the needle marker's frame.
struct NeedleCalibration {
  RigidPose marker_from_base;  ///< the needle base in the marker frame: origin at the base, +x to the tip
  Eigen::Vector3d tip_in_marker_m = Eigen::Vector3d::Zero();  ///< the straight needle's tip
};

/// The scene URDF's needle: the fixed chains from needle_marker to needle_base and to
/// needle_tip (`navtool calib pivot` writes the tip). With `needle:`, the base-to-tip distance
/// must be its length_m within 1 mm. Errors name frames.urdf or needle.length_m.
Result<NeedleCalibration> scene_needle_calibration(const Scene& scene);

/// The operating loop on `liver` at the scene's rates and latency, the tracker frame equal to
/// the model frame, on the scene's liver model (see the file comment), its needle tip and base
/// where the URDF calibrates them (scene_needle_calibration). With `needle:` the loop steps the
/// scene's flexible needle coupled to every rung (at the loop rate, its base at the needle
/// marker * marker_from_base); without it, a rigid needle. With `ligaments:` the loop steps
/// them with its liver, which carries their forces (their attachment declared in its scene).
/// Errors name the scene key (liver.model.artifact, liver.model.escalation..., needle,
/// ligaments, frames.urdf).
Result<OperatingLoopModel> make_station_loop(const StationLiver& liver, const Scene& scene,
                                             const BreathingGeometry& breathing, const StationLoopSettings& settings);

/// Whether the station's loop can run the scene's liver model, checked before anything is
/// built: a ladder with the full order on top cannot (the loop's filter needs reduced
/// coordinates on every rung); an Error at liver.model.escalation.full_order_on_top; nor
/// one whose URDF has no registration (reference_marker -> liver_model), at frames.urdf.
Status check_station_loop(const Scene& scene);

/// One line that says which liver the loop runs and where it came from, e.g. "liver model:
/// reduced r = 20 (52 sampled tetrahedra) from build/liver_fine.navrb".
std::string describe_station_loop(const Scene& scene, const OperatingLoopModel& loop);

}  // namespace nav::station
