#pragma once
// Coupling of the needle-tissue constraints with the full-order tetrahedral tissue
// (TetFemModel), through the tissue's point-force inputs and a compliance estimated by
// probing the tissue at init. Multi-rate: the needle and its constraint forces step at every
// tick (1 kHz) with the last compliance, the tissue once every needle_steps_per_tissue_step
// ticks with the forces of that tick; between tissue steps the constraints see the tissue's
// response to force changes through the compliance only.
#include <array>
#include <span>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/needle/needle_tissue_model.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {

/// The tissue's compliance seen from one point: the displacement per newton of a node under
/// a force on itself over one tissue step, and the Gaussian length over which it decays.
struct ProbedCompliance {
  std::array<double, 9> tensor_m_per_n{};  ///< 3x3, column-major, symmetrised
  double point_compliance_m_per_n = 0.0;   ///< a third of its trace
  double correlation_length_m = 0.0;
};

/// Probes `tissue` at the node nearest `point_m` with `probe_force_n` along each axis (one
/// tissue step from rest each); the Error names the field at fault. Init-time.
Result<ProbedCompliance> probe_tet_fem_compliance(const TetFemModel& tissue, const Point3& point_m, double probe_force_n);

/// The immutable coupled scene: the needle-tissue model attached to the tissue's nodes.
struct CoupledNeedleModel {
  NeedleTissueModel interaction;
  const TetFemModel* tissue = nullptr;  ///< not owned; outlives this model
  int needle_steps_per_tissue_step = 1;
  std::size_t max_point_forces = 16;    ///< as the tissue scene's max_point_forces
};

/// State of the coupled scene: the interaction's data, the tissue's data, the tissue
/// displacements the interaction sees, and the point forces handed to the tissue.
struct CoupledNeedleData {
  Arena arena;
  NeedleTissueData interaction;
  TetFemData tissue;
  std::span<double> displacements_m;  ///< 3 per tissue node, as of the last tissue step
  std::span<PointForce> point_forces;
  std::int64_t ticks = 0;
  int dropped_point_forces = 0;  ///< forces beyond max_point_forces at the last tissue step
  CoupledNeedleData(Arena block, NeedleTissueData interaction_data, TetFemData tissue_data)
      : arena(std::move(block)), interaction(std::move(interaction_data)), tissue(std::move(tissue_data)) {}
};

/// Builds the coupled model; the scene's point compliance and correlation length are
/// replaced by those probed at the first layer's surface point.
Result<CoupledNeedleModel> make_coupled_needle_model(const NeedleParameters& needle, const NeedleTissueScene& scene,
                                                     const TetFemModel& tissue, std::size_t max_point_forces,
                                                     int needle_steps_per_tissue_step);

Result<CoupledNeedleData> make_coupled_needle_data(const CoupledNeedleModel& model, const NeedlePose& base);

/// One needle tick; the tissue steps on every needle_steps_per_tissue_step-th tick. More
/// distinct loaded nodes than max_point_forces: the smallest forces are dropped and pool_full raised.
void step(const CoupledNeedleModel& model, CoupledNeedleData& data, const NeedleInputs& inputs) noexcept;

}  // namespace nav
