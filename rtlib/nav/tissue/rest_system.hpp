#pragma once
// Init-time linear algebra of a TetFemModel at its rest shape: the coefficients of the
// implicit system, its sparse LDL^T, its block-diagonal preconditioners and the explicit
// stable-step estimate. Internal.
#include "nav/core/error.hpp"
#include "nav/tissue/tet_fem_tables.hpp"

namespace nav::detail {

/// Fills the system coefficients, preconditioners, factor (for ldlt_warped) and
/// stable_step_s of `tables`, whose elements, masses and supports are already built.
/// Errors when the system of an implicit or quasi-static model cannot be factored.
Status build_rest_system(TetFemTables& tables);

}  // namespace nav::detail
