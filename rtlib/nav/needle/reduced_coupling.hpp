#pragma once
// Coupling of the needle-tissue constraints with the reduced-order tissue (ReducedModel,
// u = U q): the constraint forces enter the reduced step as point forces (U^T H^T f); the
// tissue compliance at the constraint points is the reduced basis's own,
// W_tissue = H U G U^T H^T, with G the change of q per unit generalized force over one
// reduced step (h^2 S^-1 for implicit Euler, S^-1 quasi-static; S the frozen, prefactored
// system matrix), kept as V = U L with G = L L^T so that W_tissue costs O(k^2 r) for k rows;
// and the tissue points' displacements are rebuilt from q at the nodes the interaction refers
// to only, plus a round-robin block of the other nodes (for the nearest-node search of new
// tissue points). The tick, multi-rate included, is coupled_needle.hpp's step().
#include <span>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/needle/coupled_needle.hpp"
#include "nav/reduced/reduced_model.hpp"

namespace nav {

/// The reduced tissue's compliance at its nodes, as factor rows V (3 per node, `rank` values
/// each, row-major): node b moves by V_b V_a^T f over one step under a force f on node a.
struct ReducedComplianceFactors {
  int rank = 0;
  std::vector<double> factors;
};

/// The probe force of the coupling's factors: small against a needle's forces, large against
/// rounding (the step is linear in it for a frozen tangent).
inline constexpr double kComplianceProbeForceN = 0.01;

/// Probes `tissue` through its public step (init time): the basis U from reconstructions
/// of unit coordinates, G from one step from rest under `probe_force_n` on r well-conditioned
/// node axes (column-pivoted QR of U^T), symmetrised and factored. Exact for a frozen tangent
/// and one Newton iteration (the step is then linear in the point forces); otherwise the
/// linearisation at rest. Errors name the field at fault.
Result<ReducedComplianceFactors> reduced_compliance_factors(const ReducedModel& tissue, double probe_force_n);

/// The needle coupled to the reduced tissue, and its state.
using ReducedCoupledNeedleModel = CoupledNeedleModelOf<ReducedModel>;
using ReducedCoupledNeedleData = CoupledNeedleDataOf<ReducedData>;

/// Builds the coupled model on `tissue`, built on `mesh` (whose rest nodes the tissue points
/// attach to); `max_point_forces` must not exceed the reduced model's scene's (checked).
Result<ReducedCoupledNeedleModel> make_coupled_needle_model(const NeedleParameters& needle,
                                                            const NeedleTissueScene& scene, const ReducedModel& tissue,
                                                            const TetMesh& mesh, std::size_t max_point_forces,
                                                            int needle_steps_per_tissue_step);

Result<ReducedCoupledNeedleData> make_coupled_needle_data(const ReducedCoupledNeedleModel& model,
                                                          const NeedlePose& base);

}  // namespace nav
