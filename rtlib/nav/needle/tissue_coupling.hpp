#pragma once
// Coupling of the needle-tissue constraints with the full-order tetrahedral tissue
// (TetFemModel), through the tissue's point-force inputs and its compliance: its response
// over one step at the constraint points' nodes (solves with its rest factor), or, without
// that factor, one probed at init (a 3x3 tensor with a Gaussian decay between points). The tick,
// multi-rate included, is coupled_needle.hpp's step(); between tissue steps the constraints
// see the tissue's response to force changes through the compliance only.
#include <array>
#include <span>

#include "nav/core/error.hpp"
#include "nav/needle/coupled_needle.hpp"
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
Result<ProbedCompliance> probe_tet_fem_compliance(const TetFemModel& tissue, const Point3& point_m,
                                                  double probe_force_n);

/// The needle coupled to the full-order tissue, and its state.
using CoupledNeedleModel = CoupledNeedleModelOf<TetFemModel>;
using CoupledNeedleData = CoupledNeedleDataOf<TetFemData>;

/// Builds the coupled model. A tissue with a rest factor that steps implicitly
/// (has_rest_step_response) gives its own response at the constraint points' nodes, solved as
/// they come into use and cached (the scene's point compliance is then the local compliance
/// of a point about its node: tissue points a few millimetres apart on one node move
/// together without it, and W loses its definiteness); otherwise the scene's point compliance and correlation
/// length are replaced by those probed at the first layer's surface point.
Result<CoupledNeedleModel> make_coupled_needle_model(const NeedleParameters& needle, const NeedleTissueScene& scene,
                                                     const TetFemModel& tissue, std::size_t max_point_forces,
                                                     int needle_steps_per_tissue_step);

Result<CoupledNeedleData> make_coupled_needle_data(const CoupledNeedleModel& model, const NeedlePose& base);

}  // namespace nav
