#pragma once
// Step-time solution of the implicit or quasi-static system of a TetFemModel,
// A x = b with A = a M + b K_R + c Ks over free nodes: the warped rest LDL^T, or
// preconditioned conjugate gradients with a fixed iteration count. Internal.
#include "nav/tissue/tet_fem_model.hpp"

namespace nav::detail {

/// Solves A data.solution = data.rhs (constrained entries of rhs must be zero; those of the
/// solution come out zero). Uses data.element_rotations (and updates data.node_rotations
/// when the solver warps). Reports the CG residual and iterations in data.report.
void solve_system(const TetFemTables& tables, TetFemData& data) noexcept;

}  // namespace nav::detail
