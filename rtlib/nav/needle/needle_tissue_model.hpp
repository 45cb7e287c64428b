#pragma once
// Needle-tissue interaction as constraints (Duriez, section 2.5): a puncture state machine
// per layer, cutting at the tip, shaft friction with stick and slip, path constraints from a
// preallocated pool, and the bevel's steering behind a switch, solved by projected
// Gauss-Seidel on W = H A^-1 H^T + W_tissue after the needle's free motion, then corrected.
// Model/Data: the model is immutable after init, the data is one arena, step() is noexcept,
// allocation-free, of fixed cost and bitwise repeatable.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/needle/constraint_row.hpp"
#include "nav/needle/needle_lane_kernels.hpp"
#include "nav/needle/needle_model.hpp"
#include "nav/needle/needle_tissue_scene.hpp"
#include "nav/needle/node_pair_compliance.hpp"
#include "nav/needle/surface_bvh.hpp"

namespace nav {

class TetFemModel;

/// Where the tip stands with one layer.
enum class LayerPhase : std::uint8_t {
  outside,    ///< not touching (possibly holed by an earlier puncture)
  touching,   ///< on the surface, pushing it in up to f_p
  punctured,  ///< the surface gave way; the layer has a hole and a cut front
};

/// A material point of the tissue: its rest position and the tissue node whose displacement
/// carries it (-1 when the tissue does not move as a whole, as in the stand-alone scene).
struct TissuePoint {
  Eigen::Vector3d rest_m = Eigen::Vector3d::Zero();
  std::int32_t node = -1;
};

/// The state of one layer.
struct LayerState {
  LayerPhase phase = LayerPhase::outside;
  bool holed = false;
  TissuePoint surface;  ///< the layer's surface point, carried by its nearest tissue node
  TissuePoint contact;  ///< the surface point under the tip while touching
  /// The surface's outward normal where the tip first touched it: while touching, the tip
  /// pushes on that tangent plane, carried by the contact point (the dent under the tip
  /// leaves it alone).
  Eigen::Vector3d contact_normal = Eigen::Vector3d::UnitZ();
  TissuePoint hole;       ///< where the surface was punctured
  TissuePoint cut_front;  ///< the deepest point cut so far
};

/// One path constraint: a tissue point held on the needle at needle arclength s.
struct PathPoint {
  bool active = false;
  double arclength_m = 0.0;
  TissuePoint tissue;
  std::int32_t layer = 0;
};

/// The largest rank of a low-rank tissue compliance.
inline constexpr int kMaxComplianceRank = 256;

/// The immutable interaction: the needle, the scene and the pool sizes.
struct NeedleTissueModel {
  NeedleModel needle;
  NeedleTissueScene scene;
  double bevel_tilt_rad = 0.0;  ///< 0 unless bevel_steering
  /// The tissue's 3x3 point compliance (m/N): scene.point_compliance_m_per_n times the
  /// identity, or the tensor probed from a tissue model.
  Eigen::Matrix3d compliance_tensor_m_per_n = Eigen::Matrix3d::Identity();
  /// A low-rank tissue compliance when compliance_rank > 0 (from a reduced basis): node a's
  /// 3 x rank factor rows V_a (row-major, 3 * rank values per node), node b moving by
  /// V_b V_a^T f under a force f on node a. It replaces the tensor and its Gaussian decay;
  /// tissue points are then carried by nodes, and scene.point_compliance_m_per_n is the local
  /// compliance the basis misses (its residual flexibility), isotropic at each constraint
  /// point under that point's own force. Without it rows of nearby points on one needle
  /// element can outnumber what needle and basis can follow, and W is singular.
  int compliance_rank = 0;
  std::vector<double> compliance_factors;
  /// With low-rank factors: the compliance the tissue model misses between the constraint
  /// points' nodes, beyond the factors' (e.g. the full order's, missing_node_compliance()),
  /// which the needle meets under its whole forces; scene.point_compliance_m_per_n adds to it
  /// isotropically on each point's own rows. Empty: that scalar alone.
  NodePairCompliance missing_compliance;
  /// A full-order tissue whose response over one step at the constraint points' nodes (three
  /// solves with its rest factor per node, rest_step_response_m(), kept in the data's cache
  /// while the node is in use) is the tissue's compliance between them, replacing the tensor
  /// and its Gaussian decay as the low-rank factors do. Not owned; outlives this model.
  const TetFemModel* node_response_source = nullptr;
  /// Tissue rest positions (3 per node) that tissue points attach to; empty stand-alone.
  std::vector<double> tissue_rest_m;
  /// The hierarchies of scene.surfaces, in their order.
  std::vector<detail::SurfaceBvh> surface_bvhs;
  /// The Gauss-Seidel lane kernels of scene.kernel_isa.
  const detail::NeedleLaneKernels* lane_kernels = &detail::needle_lane_kernels_baseline;
  int layer_count() const { return static_cast<int>(scene.layers.size()); }
  /// The tissue's compliance is known node by node (low-rank factors or full-order responses).
  bool nodal_compliance() const { return compliance_rank > 0 || node_response_source != nullptr; }
  /// Slots of the full-order response cache: every constraint point's node, and a few more.
  int response_slots() const { return node_response_source != nullptr ? max_points() + 4 : 0; }
  /// Constraint points at most: one per layer (contact), the tip, one per path point.
  int max_points() const { return layer_count() + 1 + scene.max_path_points; }
  /// Slots of forces: 3 per layer (contact), 1 at the tip (cutting), 3 per path point.
  int slot_count() const { return 3 * layer_count() + 1 + 3 * scene.max_path_points; }
  int tip_slot() const { return 3 * layer_count(); }
  /// Values of NeedleTissueData::surface_boxes: 6 per hierarchy node of every surface.
  std::size_t surface_box_values() const {
    return surface_bvhs.empty() ? 0 : surface_bvhs.back().box_offset + 6 * surface_bvhs.back().nodes.size();
  }
  int path_slot(int point) const { return 3 * layer_count() + 1 + 3 * point; }
};

/// What drives one interaction step.
struct NeedleTissueInputs {
  NeedleInputs needle;
  /// Displacement of the tissue nodes (3 per node), empty stand-alone.
  std::span<const double> tissue_displacements_m;
};

/// Insertion force along the base axis, positive when it resists insertion, and its parts.
struct InsertionForces {
  double total_n = 0.0;
  double stiffness_n = 0.0;  ///< surfaces pushed before they give way
  double cutting_n = 0.0;
  double friction_n = 0.0;  ///< shaft friction
};

/// What the last interaction step did.
struct NeedleTissueReport {
  InsertionForces forces;
  double contact_force_n = 0.0;  ///< largest normal force on a touched surface
  double residual_m = 0.0;       ///< largest law violation after the fixed Gauss-Seidel sweeps
  int active_rows = 0;
  int active_path_points = 0;
  int lost_path_points = 0;  ///< path points that found the pool full, since the data was made
  int punctures = 0;         ///< surfaces punctured, since the data was made
  double tip_depth_m = 0.0;  ///< tip depth below the outermost surface
};

namespace detail {

/// Workspace of the low-rank compliance W = H C H^T over the needle's translational
/// freedoms and the distinct tissue nodes' (C block-diagonal: the needle's compliance, read
/// in NeedleData, and the tissue's V_a V_b^T), each row of H with 9 entries: 3 per needle
/// node it weighs, 3 on its tissue node.
struct LowRankWorkspace {
  std::span<double> tissue_compliance;             ///< dense, row-major, 3 per distinct tissue node
  std::span<double> coefficients;                  ///< 9 per row: H's entries
  std::span<std::int32_t> local_sources, sources;  ///< 9 per row: their freedoms, in each part, in both
  std::span<double> row_fields;                    ///< per row, C H^T's column (needle then tissue freedoms)
  std::span<double> fields;                        ///< its transpose: per freedom, one value per row
};

}  // namespace detail

/// State and workspace of the interaction, in one arena (the needle keeps its own).
struct NeedleTissueData {
  Arena arena;
  NeedleData needle;
  HealthFlags health;
  NeedleTissueReport report;
  std::int64_t steps = 0;
  std::span<LayerState> layers;
  std::span<PathPoint> path;
  TissuePoint tip_anchor;            ///< the tissue point at the tip (where the next path point goes)
  std::span<double> surface_boxes;   ///< the surfaces' hierarchies' boxes at the last refresh_surfaces()
  std::span<double> slot_forces;     ///< per slot: last solution (warm start)
  std::span<double> applied_forces;  ///< per slot: forces the tissue model already carries
  // Workspace of one step.
  std::span<ConstraintRow> rows;
  std::span<double> compliance, row_forces, row_gaps, nodal_forces;
  std::size_t compliance_stride = 0;       ///< between W's rows: row_count padded to whole kernel lanes
  std::span<detail::SweepRow> sweep_rows;  ///< the Gauss-Seidel workspace
  // Nodal compliance only: the distinct tissue nodes of the constraint points and each
  // point's index among them (and, full order, each distinct node's response slot).
  std::span<std::int32_t> distinct_tissue_nodes, point_tissue_index, distinct_response_slot;
  // Full order only: per cache slot its node (-1: empty) and the step that last used it, the
  // slots' responses (3 columns of 3 per tissue node each, metres per newton) and the solves' work.
  std::span<std::int32_t> response_nodes;
  std::span<std::int64_t> response_used;
  std::span<double> responses_m_per_n, response_work;
  detail::LowRankWorkspace low_rank;
  int distinct_tissue_node_count = 0;
  std::span<std::int32_t> point_first_row;  ///< per constraint point (and one past the last), its first row
  int row_count = 0;
  int point_count = 0;  ///< constraint points of the rows (see same_constraint_point)

  NeedleTissueData(Arena block, NeedleData needle_data) : arena(std::move(block)), needle(std::move(needle_data)) {}
};

/// Builds the model; the Error names the field at fault (needle.*, scene.*).
/// `tissue_rest_m` (3 per node) lets tissue points attach to the nearest tissue node.
Result<NeedleTissueModel> make_needle_tissue_model(const NeedleParameters& needle, const NeedleTissueScene& scene,
                                                   std::span<const double> tissue_rest_m = {});

/// The data, with the needle straight at `base`, no layer touched and empty pools.
Result<NeedleTissueData> make_needle_tissue_data(const NeedleTissueModel& model, const NeedlePose& base);

/// Refits the surfaces' hierarchies to the tissue displacements (3 per node; empty: at rest):
/// after every change of the displacements the step is given (a tissue step), never between.
void refresh_surfaces(const NeedleTissueModel& model, NeedleTissueData& data,
                      std::span<const double> displacements_m) noexcept;

/// One step: pose check, needle free motion, constraints, Gauss-Seidel, correction, state
/// machines and pools. A refused pose leaves everything untouched (flags raised).
void step(const NeedleTissueModel& model, NeedleTissueData& data, const NeedleTissueInputs& inputs) noexcept;

/// The tissue's force on the needle's tip after the last step: the sum of its tip rows'
/// forces (contact and cutting) along their directions.
Eigen::Vector3d tip_force_n(const NeedleTissueModel& model, const NeedleTissueData& data) noexcept;

/// The current position of a tissue point, given the tissue displacements (may be empty).
Eigen::Vector3d tissue_point_position_m(const TissuePoint& point, std::span<const double> displacements_m) noexcept;

}  // namespace nav
