#pragma once
// The local compliance a reduced tissue misses under a needle's constraint points, node by
// node, from a full-order tissue of the same mesh (NeedleTissueModel::node_local_compliance_m_per_n).
#include <vector>

#include "nav/core/error.hpp"
#include "nav/needle/needle_tissue_model.hpp"

namespace nav {

class TetFemModel;

/// For every node of `coupled`'s low-rank compliance (a reduced tissue's factors V): the
/// full-order response over one step at the node to a force on the node itself
/// (rest_step_response_m(), 3 solves with `full`'s rest factor), less the reduced one
/// (V_n V_n^T), symmetrised, its negative eigenvalues dropped: 6 values per node (xx, xy, xz,
/// yy, yz, zz), zero on the nodes `full` constrains. `full` must be on the same mesh and step as
/// the reduced model does (quasi-static, or implicit over the same step). Init time; errors
/// name the field at fault.
Result<std::vector<double>> missing_node_compliance(const NeedleTissueModel& coupled, const TetFemModel& full);

}  // namespace nav
