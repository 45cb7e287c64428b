#pragma once
// The compliance a reduced tissue misses under a needle's constraint points, between nearby
// nodes, from a full-order tissue of the same mesh (NeedleTissueModel::missing_compliance).
#include "nav/core/error.hpp"
#include "nav/needle/node_pair_compliance.hpp"
#include "nav/needle/reduced_coupling.hpp"

namespace nav {

class TetFemModel;

/// For every node a of a reduced tissue's compliance factors V (reduced_compliance_factors())
/// and every node b within `radius_m` of it at rest (a itself included): the full-order
/// response over one step at a to a force on b (rest_step_response_m(), 3 solves with `full`'s
/// rest factor per node), less the reduced one V_a V_b^T. The blocks between distinct nodes are
/// tapered by Wendland's compactly supported function of their distance over radius_m,
/// (1 - s)^4 (4 s + 1), which keeps the table positive semi-definite as the untruncated
/// difference is (a Schur product); a node's own block is symmetrised with its negative
/// eigenvalues dropped. Nothing on the nodes `full` constrains. `full` and the factors must
/// answer for the same step: both quasi-static (the static compliance, what a needle meets of
/// a tissue that never carries it), or both implicit over the same step. Init time; errors
/// name the field at fault.
Result<NodePairCompliance> missing_node_compliance(const ReducedComplianceFactors& reduced, const TetFemModel& full,
                                                   double radius_m = 0.0);

/// The static compliance `liver` misses of the quasi-static `full` between nodes within
/// `radius_m`: missing_node_compliance() against the factors of the liver's quasi-static twin
/// (with_solver_options()), what a needle meets of a tissue that never carries it.
Result<NodePairCompliance> static_missing_node_compliance(const ReducedModel& liver, const TetFemModel& full,
                                                          double radius_m);

}  // namespace nav
