#pragma once
// Step-time boundary conditions and external loads of a TetFemModel: the check of the
// inputs at the boundary, kinematic nodes, gravity, point and area forces, frame springs
// and the spherical probe. Internal; noexcept and allocation-free.
#include <span>

#include "nav/tissue/tet_fem_tables.hpp"

namespace nav::detail {

/// True when every input value is finite, every point-force node exists, there are at most
/// max_point_forces of them, the frame's quaternion is not zero and the probe radius is not
/// negative.
bool inputs_are_valid(const TetFemTables& tables, const TissueInputs& inputs) noexcept;

/// Puts fixed nodes at rest and prescribed nodes at rest + the prescribed displacement, with
/// the velocity that took them there over `step_s` (zero when step_s is 0).
void move_kinematic_nodes(const TetFemTables& tables, const TissueInputs& inputs, double step_s, std::span<double> x,
                          std::span<double> v) noexcept;

/// forces += gravity, point forces and traction (times inputs.load_scale), frame springs and
/// probe at positions x.
void add_external_forces(const TetFemTables& tables, const TissueInputs& inputs, std::span<const double> x,
                         std::span<double> forces, TissueStepReport& report) noexcept;

/// out += scale * Ks p, with Ks the frame springs' stiffness.
void add_spring_product(const TetFemTables& tables, std::span<const double> p, double scale,
                        std::span<double> out) noexcept;

/// Zeroes the entries of constrained (fixed and prescribed) nodes.
void zero_constrained(const TetFemTables& tables, std::span<double> v) noexcept;

}  // namespace nav::detail
