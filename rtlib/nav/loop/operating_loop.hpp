#pragma once
// The deterministic tick of the station's real-time loop: it brings the tracked tool poses to
// the tick's time, drives the reduced liver's diaphragm from the breathing marker, steps the
// liver every Nth tick (multi-rate), assimilates the ultrasound's view of the tumour with the
// reduced Kalman filter, and publishes the tumour now and at now + display latency (with
// covariances), the needle tip and its distance to the tumour, and the health of every input.
// The diaphragm follows the newest marker sample, moved on by the breathing model's change
// since that sample (delay compensated, irregular breaths followed at once); observations are
// carried from their capture time to the liver step by the diaphragm lift's motion in between.
// Optionally the loop steps a flexible needle coupled to the reduced liver: every tick the
// needle's base follows the tracked needle pose, and the liver steps carry the needle's point
// forces with the diaphragm (see OperatingLoopNeedleOptions).
// Optionally the liver is an escalation ladder of reduced rungs (ReducedLadderModel): when the
// active rung's indicator fires and the ladder allows it, the liver's state before the step,
// the filter's correction and covariance and the needle are carried one rung up and the step
// is redone there; with de-escalation on, the loop steps back down once the state fits the
// rung below (see operating_loop_ladder.cpp).
// Optionally frame-based ligaments hang the liver (OrganLigaments): every liver step first
// steps them at the liver's attachment nodes and the liver then carries their forces with the
// needle's (the staggered, stabilised scheme of organ_attachment.hpp).
// Model/Data: the model is built at init and immutable; push_* and tick() are noexcept,
// allocation-free, fixed-cost and bitwise repeatable. Faults flag and degrade, never stop.
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "nav/connective/organ_ligaments.hpp"
#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/fusion/breathing_predictor.hpp"
#include "nav/fusion/pose_track.hpp"
#include "nav/fusion/reduced_kalman.hpp"
#include "nav/fusion/rigid_pose.hpp"
#include "nav/needle/reduced_coupling.hpp"
#include "nav/reduced/reduced_ladder.hpp"
#include "nav/reduced/reduced_model.hpp"

namespace nav {

class TetFemModel;

/// The largest reduced basis an operating loop carries in its outputs (the displayed liver state).
inline constexpr int kLoopMaxBasisSize = 64;

/// The most needle nodes an operating loop's outputs carry (a needle of up to 64 elements).
inline constexpr int kLoopMaxNeedleNodes = 65;

/// The needle model as a tick leaves it (model frame); empty (node_count 0) when the loop
/// steps no needle model and only tracks the needle's tip.
struct NeedleShapeOutputs {
  int node_count = 0;                                      ///< 0: no needle model
  std::array<Point3, kLoopMaxNeedleNodes> centreline_m{};  ///< node positions, base first, tip last
  Point3 tip_force_n{};      ///< the tissue's force on the needle's tip (its contact and cutting constraints)
  Point3 base_force_n{};     ///< the needle's force on its holder (what the hand feels; up the needle when the tissue
                             ///< resists)
  double tip_depth_m = 0.0;  ///< tip depth below the outermost surface (0 outside)
  int punctures = 0;         ///< surfaces punctured since the loop started
  RigidPose base_pose;       ///< the base (holder) pose the needle stepped with, model frame
  /// The needle-tissue interaction's flags of this tick: a refused base pose (bad_sample),
  /// solver_not_converged, pool_full, non_finite_state, and pose_jump_rejected while the base
  /// glides to a re-acquired pose too far for one step.
  HealthFlags flags;
};

/// Rates, latencies, geometry and input options of an operating loop; checked at build.
struct OperatingLoopOptions {
  TimeNs tick_period_ns = kNsPerMs;            ///< the loop's period (1 kHz)
  int tissue_every_ticks = 20;                 ///< the liver steps every Nth tick: N tick periods must equal its step_s
  TimeNs display_latency_ns = 100 * kNsPerMs;  ///< from a tick to the display showing its frame
  /// The needle tip in the needle marker's frame (metres); with a needle model the rigid tip
  /// is its straight tip instead (OperatingLoopNeedleModel::tip_in_marker_m).
  Eigen::Vector3d needle_tip_in_marker_m = Eigen::Vector3d::Zero();
  /// The tracker's frame in the model (mesh) frame: applied to every tool pose.
  RigidPose model_from_tracker;
  /// The diaphragm displacement (model frame) per metre of respiratory marker displacement
  /// along breathing.axis, measured from respiratory_reference_m.
  Eigen::Vector3d diaphragm_per_marker = Eigen::Vector3d::Zero();
  double respiratory_reference_m = 0.0;           ///< marker displacement at which the diaphragm is at rest
  PoseTrackOptions needle, probe;                 ///< the two tracked tools
  BreathingPredictorOptions breathing;            ///< the respiratory marker (axis in the tracker frame)
  std::size_t max_pending_observations = 8;       ///< ultrasound observations held between tissue ticks
  TimeNs ultrasound_max_age_ns = 250 * kNsPerMs;  ///< no accepted observation for longer: stale_input
};

/// A flexible needle for the loop to step, coupled to its reduced liver. Its base is the
/// tracked needle marker's pose times marker_from_base, every tick; it stays idle (node_count 0,
/// no force) until the first good needle pose, which places it straight there; while the
/// needle input is degraded its base is held at the last good pose. The tissue steps with the
/// loop's liver (every tissue_every_ticks ticks) under the needle's forces and the diaphragm.
struct OperatingLoopNeedleOptions {
  NeedleParameters parameters;  ///< parameters.step_s must equal the tick period; at most kLoopMaxNeedleNodes nodes
  NeedleTissueScene scene;      ///< the layers the needle meets, model frame
  RigidPose marker_from_base;   ///< the needle base (holder) in the marker frame; the needle along +x
  std::size_t max_point_forces = 16;  ///< at most the reduced model's scene's max_point_forces
  /// A quasi-static full-order liver on the rungs' mesh with its rest factor (ldlt_warped):
  /// each rung's needle then meets, beyond its basis, the static compliance the basis misses
  /// between the constraint points' nodes within missing_compliance_radius_m of each other
  /// (missing_node_compliance() against the rung's quasi-static twin). The tissue never carries
  /// that part: the needle meets it under its whole forces, as the tissue would yield at rest
  /// under them (the basis's own part follows the liver's dynamics). Read while the loop is
  /// built, not kept. Null: the scene's point compliance alone.
  const TetFemModel* missing_compliance_source = nullptr;
  double missing_compliance_radius_m = 0.0;
};

/// The needle of a loop: the needle coupled to the loop's reduced liver. The coupled model
/// points to `tissue` (a handle sharing the liver's tables), so this object never moves: the
/// loop model holds it behind a shared pointer and can itself be moved and copied.
struct OperatingLoopNeedleModel {
  ReducedModel tissue;                ///< the loop's reduced model
  ReducedCoupledNeedleModel coupled;  ///< coupled.tissue == &tissue
  RigidPose marker_from_base;
  Eigen::Vector3d tip_in_marker_m = Eigen::Vector3d::Zero();  ///< the straight needle's tip, marker frame

  OperatingLoopNeedleModel(ReducedModel liver, const RigidPose& base, double length_m)
      : tissue(std::move(liver)),
        marker_from_base(base),
        tip_in_marker_m(base.rotation * Eigen::Vector3d(length_m, 0.0, 0.0) + base.position_m) {}
  OperatingLoopNeedleModel(const OperatingLoopNeedleModel&) = delete;
  OperatingLoopNeedleModel& operator=(const OperatingLoopNeedleModel&) = delete;
};

/// A rigid pose as a needle base pose.
inline NeedlePose to_needle_pose(const RigidPose& pose) noexcept {
  const Eigen::Quaterniond& q = pose.rotation;
  return {{pose.position_m[0], pose.position_m[1], pose.position_m[2]}, {q.w(), q.x(), q.y(), q.z()}};
}

/// One rung of the loop's liver: a reduced model, the filter observing the tumour on it (its
/// point 0), optionally the needle coupled to it, and the maps from the rung below.
struct OperatingLoopRung {
  ReducedModel reduced{nullptr};
  ReducedKalmanModel filter;
  std::shared_ptr<const OperatingLoopNeedleModel> needle;  ///< null: the needle is tracked as a rigid tip
  double lookahead_decay = 1.0;                            ///< the filter's decay a^lookahead_steps
  /// From the rung below (empty on rung 0), row-major: T = U^T M U_below (r x r_below), its
  /// transpose (the M-projection down, r_below x r) and the filter's prior covariance of the
  /// directions the rung below lacks (r x r, see unseen_directions_prior).
  std::vector<double> up_from_below, down_to_below, unseen_prior;
};

/// The immutable part of a loop: its liver's rungs (one without a ladder), the ladder they
/// come from, the options and what follows from them.
struct OperatingLoopModel {
  std::vector<OperatingLoopRung> rungs;      ///< rung 0 first, growing r
  std::optional<ReducedLadderModel> ladder;  ///< with more than one rung: their envelopes and moves
  OperatingLoopOptions options;
  /// Ligaments hanging the liver (null: none); the liver's scene declares their attachment.
  std::shared_ptr<const OrganLigaments> ligaments;
  int lookahead_steps = 1;  ///< reduced steps from a tissue tick to it + display latency
  Eigen::Vector3d breathing_axis = Eigen::Vector3d::UnitZ();  ///< options.breathing.axis, normalised
  bool has_needle() const { return rungs.front().needle != nullptr; }
};

/// The health of one input at a tick.
struct InputStatus {
  HealthFlags flags;     ///< of the tick's lookup and of the samples pushed since the last tick
  bool degraded = true;  ///< the input's value is held, extrapolated too far, or missing
  TimeNs age_ns = std::numeric_limits<TimeNs>::max();  ///< tick time minus the newest good sample's (max: none yet)
};

/// What one tick publishes. Positions in the model frame, metres.
struct OperatingLoopOutputs {
  TimeNs time_ns = 0;         ///< the tick's time
  TimeNs tissue_time_ns = 0;  ///< the tick of the last liver step (the tumour values' time)
  std::int64_t ticks = 0, tissue_steps = 0;
  Point3 tumour_now_m{};                             ///< Kalman estimate at tissue_time_ns
  std::array<double, 9> tumour_now_covariance_m2{};  ///< row-major 3x3
  Point3 tumour_ahead_m{};                           ///< predicted at tissue_time_ns + display latency
  std::array<double, 9> tumour_ahead_covariance_m2{};
  /// At the tick's time: the rigid tracked tip, or with a needle model its modelled (bent) tip
  /// (the tracked tip before the needle is first seen).
  Point3 needle_tip_m{};
  /// At the tick's time + display latency: the rigid tracked tip extrapolated, plus with a
  /// needle model the current bend (modelled tip minus the rigid tip at the tick's time).
  Point3 needle_tip_ahead_m{};
  double tip_to_tumour_m = 0.0;        ///< |needle tip - tumour now|
  double tip_to_tumour_ahead_m = 0.0;  ///< |needle tip ahead - tumour ahead|
  NeedleShapeOutputs needle_shape;     ///< the needle model's shape and forces at the tick's time
  RigidPose probe_pose;                ///< the ultrasound probe at the tick's time
  Point3 diaphragm_m{};                ///< the diaphragm displacement driving the last liver step
  /// The displayed liver at tissue_time_ns: reduced coordinates q + dq (model and filter
  /// correction) of rung liver_rung (its first r are used), with diaphragm_m the whole
  /// deformed state (see liver_displacements_m).
  std::array<double, kLoopMaxBasisSize> liver_q{};
  int liver_rung = 0;                                ///< the ladder's rung of the last liver step (0 without a ladder)
  std::int64_t escalations = 0, de_escalations = 0;  ///< rung changes since the loop started
  double breathing_phase_rad = 0.0;                  ///< at the tick's time
  InputStatus needle, probe, respiratory, ultrasound;  ///< ultrasound: buffer_overrun when observations were dropped
  /// The reduced model's and the filter's flags of the last liver step (reduced_escalated when
  /// it was redone one rung up).
  HealthFlags tissue;
  HealthFlags loop;      ///< clock_went_backwards: the tick's time was not after the previous one
  bool degraded = true;  ///< any input degraded or any flag raised
};

/// A tumour observation waiting for the next liver step.
struct PendingObservation {
  TimeNs time_ns = 0;
  Point3 position_m{};
};

/// The state of one rung of the loop's liver: the liver (inside the coupled needle when the
/// loop has one), the look-ahead scratch and the filter.
struct OperatingLoopRungData {
  ReducedData reduced;    ///< the liver without a needle model (with one: needle_model->tissue)
  ReducedData lookahead;  ///< scratch: the liver stepped ahead to the display time
  ReducedKalmanData filter;
  std::optional<ReducedCoupledNeedleData> needle_model;  ///< the needle and the liver it pushes
  ReducedData& liver() noexcept { return needle_model ? needle_model->tissue : reduced; }
  const ReducedData& liver() const noexcept { return needle_model ? needle_model->tissue : reduced; }
};

/// The state of the ligaments hanging the loop's liver: their frames, the forces they leave
/// for the liver's next step, and the attachment nodes' positions they were stepped at.
struct OperatingLoopLigamentsData {
  FrameTissueData tissue;
  AttachmentBuffers buffers;
  std::vector<double> node_displacements_m;  ///< 3 per attachment node, scratch
  std::vector<double> organ_positions_m;     ///< 3 per liver node; only the attachment nodes' are kept
};

/// The loop's state: every rung's liver and filter, the ladder's position, the tool tracks,
/// the breathing predictor, the pending observations, the needle and the outputs.
struct OperatingLoopData {
  std::vector<OperatingLoopRungData> rungs;  ///< one per model rung, all allocated at init
  int active_rung = 0;
  int flagged_steps = 0;                   ///< consecutive liver steps with the indicator up
  int inside_steps = 0;                    ///< consecutive liver steps fit for the rung below
  std::vector<double> transfer_workspace;  ///< r_max^2, for carrying the filter between rungs
  PoseTrack needle, probe;
  BreathingPredictor breathing;
  std::vector<PendingObservation> pending;  ///< sized at init; the first pending_count are waiting
  std::size_t pending_count = 0;
  HealthFlags needle_push_flags, probe_push_flags, respiratory_push_flags,
      ultrasound_push_flags;                                          ///< since the last tick
  TimeNs respiratory_newest_ns = std::numeric_limits<TimeNs>::min();  ///< the newest accepted marker sample
  double respiratory_newest_m = 0.0;                                  ///< its displacement along the breathing axis
  TimeNs last_tick_ns = 0;
  RigidPose needle_base;                                ///< the last good base pose (model frame)
  bool needle_acquired = false;                         ///< a good needle pose has been seen: the needle steps
  std::optional<OperatingLoopLigamentsData> ligaments;  ///< with the model's ligaments
  OperatingLoopOutputs outputs;

  /// The active rung's state: the liver the filter and the outputs follow.
  OperatingLoopRungData& active() noexcept { return rungs[static_cast<std::size_t>(active_rung)]; }
  const OperatingLoopRungData& active() const noexcept { return rungs[static_cast<std::size_t>(active_rung)]; }

  OperatingLoopData(std::vector<OperatingLoopRungData> rung_data, std::size_t workspace_values, PoseTrack needle_track,
                    PoseTrack probe_track, BreathingPredictor breathing_predictor, std::size_t pending_capacity);
};

/// Checks the options against the reduced model and the filter (the tumour is the filter's
/// point 0) and derives the look-ahead; optionally `ligaments` hang the liver (built on its
/// mesh, their attachment declared in the scene the reduced model was built on). Errors name
/// the field at fault ("operating_loop.ligaments" for an attachment the liver does not carry).
Result<OperatingLoopModel> make_operating_loop_model(ReducedModel reduced, ReducedKalmanModel filter,
                                                     const OperatingLoopOptions& options,
                                                     std::shared_ptr<const OrganLigaments> ligaments = nullptr);

/// As above, plus the needle, coupled to the reduced liver built on `mesh` (whose rest nodes
/// carry the tissue points); the tissue steps every options.tissue_every_ticks ticks. With
/// ligaments the needle's max_point_forces and their attachment nodes share the scene's.
/// Errors name the field ("operating_loop.needle.parameters.step_s", "operating_loop.needle.<field>").
Result<OperatingLoopModel> make_operating_loop_model(ReducedModel reduced, ReducedKalmanModel filter,
                                                     const OperatingLoopOptions& options,
                                                     const OperatingLoopNeedleOptions& needle, const TetMesh& mesh,
                                                     std::shared_ptr<const OrganLigaments> ligaments = nullptr);

/// A loop whose liver is `ladder` (reduced rungs only: the filter needs a reduced state), with
/// filters[i] observing the tumour on rung i, and optionally the needle, coupled to every rung
/// (rung 0 when the loop starts), and the ligaments. The ladder's options are the loop's
/// escalation settings. Errors name the field ("operating_loop.ladder", "operating_loop.filters[i]", ...).
Result<OperatingLoopModel> make_operating_loop_model(const ReducedLadderModel& ladder,
                                                     std::vector<ReducedKalmanModel> filters,
                                                     const OperatingLoopOptions& options,
                                                     const OperatingLoopNeedleOptions* needle = nullptr,
                                                     const TetMesh* mesh = nullptr,
                                                     std::shared_ptr<const OrganLigaments> ligaments = nullptr);

/// The loop's data at rest: liver at rest on rung 0, filter at its prior, empty tracks, idle needle.
Result<OperatingLoopData> make_operating_loop_data(const OperatingLoopModel& model);

/// A needle marker pose (tracker frame) measured at time_ns.
void push_needle_pose(const OperatingLoopModel& model, OperatingLoopData& data, const TimedPose& sample) noexcept;
/// An ultrasound probe marker pose (tracker frame) measured at time_ns.
void push_probe_pose(const OperatingLoopModel& model, OperatingLoopData& data, const TimedPose& sample) noexcept;
/// A respiratory marker position (tracker frame) measured at time_ns.
void push_respiratory_sample(const OperatingLoopModel& model, OperatingLoopData& data, TimeNs time_ns,
                             const Eigen::Vector3d& position_m) noexcept;
/// The tumour seen by the ultrasound (model frame) at time_ns; assimilated at the next liver
/// step. A full queue drops its oldest entry (buffer_overrun).
void push_tumour_observation(OperatingLoopData& data, TimeNs time_ns, const Point3& position_m) noexcept;

/// Scratch liver states (one per rung) for rebuilding the displayed liver away from the
/// real-time thread.
struct LiverDisplayScratch {
  std::vector<ReducedData> rungs;
};

/// The scratch for liver_displacements_m (init time).
Result<LiverDisplayScratch> make_liver_display_scratch(const OperatingLoopModel& model);

/// Displacements from rest (3 per node, metres, model frame) of the liver shown by `outputs`
/// (on its rung) at `nodes`: the deformed display surface or any point, away from the
/// real-time thread. `scratch` belongs to the caller (its states are overwritten).
void liver_displacements_m(const OperatingLoopModel& model, const OperatingLoopOutputs& outputs,
                           LiverDisplayScratch& scratch, std::span<const std::int32_t> nodes,
                           std::span<double> out_xyz) noexcept;

/// One tick at now_ns: tool poses at now (and now + display latency), the needle model's step,
/// and every tissue_every_ticks-th tick the ligaments' step and a liver step (with the
/// needle's and the ligaments' forces; their flags join `tissue`) with the
/// filter's predict and the pending observations, then the look-ahead (carrying the same
/// needle forces). Fills data.outputs.
void tick(const OperatingLoopModel& model, OperatingLoopData& data, TimeNs now_ns) noexcept;

}  // namespace nav
