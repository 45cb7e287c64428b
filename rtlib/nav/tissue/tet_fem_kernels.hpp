#pragma once
// Step-time element loops of a TetFemModel: element and node rotations, internal forces,
// products with the rotated stiffness, elastic energy. All noexcept and allocation-free;
// elements are visited in index order so that sums are bitwise repeatable. Internal.
#include <span>

#include "nav/tissue/tet_fem_tables.hpp"

namespace nav::detail {

/// Recomputes each element's rotation from positions `x` (identity for linear models).
/// An element with det F <= 0 keeps its previous rotation; returns how many there were.
int update_element_rotations(const TetFemTables& tables, std::span<const double> x,
                             std::span<double> rotations) noexcept;

/// How many elements have det F <= 0 at positions x (or a non-finite one).
int count_inverted_elements(const TetFemTables& tables, std::span<const double> x) noexcept;

/// Node rotations for warping: the polar factor of the sum of the adjacent elements' rotations.
void update_node_rotations(const TetFemTables& tables, std::span<const double> element_rotations,
                           std::span<double> node_rotations) noexcept;

/// Adds the elastic restoring forces at positions x: -R K_e (R^T x - X) per element for the
/// linear law, -V0 P(F) grad^T for St Venant-Kirchhoff.
void add_elastic_forces(const TetFemTables& tables, std::span<const double> x, std::span<const double> rotations,
                        std::span<double> forces) noexcept;

/// St Venant-Kirchhoff only: stores the stress each element's tangent is taken with at
/// positions x (stvk_tangent_stress, 9 per element, column-major). Does nothing for the
/// linear law.
void update_tangent_stresses(const TetFemTables& tables, std::span<const double> x,
                             std::span<double> tangent_stresses) noexcept;

/// out += scale * K p, with K the stiffness at positions x: the linear stiffness rotated by
/// each element's rotation, or the positive semi-definite St Venant-Kirchhoff tangent with
/// the stresses of update_tangent_stresses.
void add_stiffness_product(const TetFemTables& tables, std::span<const double> x, std::span<const double> rotations,
                           std::span<const double> tangent_stresses, std::span<const double> p, double scale,
                           std::span<double> out) noexcept;

/// Elastic energy of positions `x` in joules (linear law: each element in its own polar
/// rotation).
double elastic_energy(const TetFemTables& tables, std::span<const double> x) noexcept;

}  // namespace nav::detail
