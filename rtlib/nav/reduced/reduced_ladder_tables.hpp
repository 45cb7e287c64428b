#pragma once
// The precomputed tables of a ReducedLadderModel, shared by its build and step. Internal to
// rtlib/nav/reduced. Matrices are row-major.
#include <cstdint>
#include <optional>
#include <vector>

#include "nav/reduced/reduced_ladder.hpp"

namespace nav::detail {

/// Per-ladder tables of a ReducedLadderModel.
struct ReducedLadderTables {
  ReducedLadderOptions options;
  std::int64_t node_count = 0;
  std::vector<ReducedModel> rungs;            ///< the reduced rungs, growing r
  std::vector<int> sizes;                     ///< r of each reduced rung
  std::vector<std::vector<double>> q_bound;   ///< per reduced rung: its training bounds (r, or empty)
  std::vector<std::vector<double>> transfer;  ///< transfer[i]: r_{i+1} x r_i, U_{i+1}^T M U_i
  std::vector<double> transfer_loss;          ///< per transfer: 1 - min squared column norm
  std::optional<TetFemModel> full;            ///< the full-order rung
  // With the full order: the top reduced rung's basis (3 node_count x r), the lift
  // (3 node_count x 3, empty without one) and the lumped mass of every dof.
  std::vector<double> top_rows, lift_rows, dof_mass_kg;
  int max_r = 0;
};

}  // namespace nav::detail
