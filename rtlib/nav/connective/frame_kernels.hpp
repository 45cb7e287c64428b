#pragma once
// Step-time point loops of a FrameTissueModel: frame rotations, the deformation gradient of
// every integration point (eq. 8), St Venant-Kirchhoff forces on the frames (eqs. 17-18),
// products with the tangent (eqs. 23-25) and its assembly. Points are visited in index
// order, so sums are bitwise repeatable. noexcept and allocation-free. Internal.
#include <span>

#include "nav/connective/frame_tables.hpp"

namespace nav::detail {

/// Caches of the point loops, all carved from FrameTissueData.
struct FrameWorkspace {
  std::span<const double> positions_m;  ///< 3 per frame
  std::span<const double> rotations;    ///< 9 per frame, column-major
  std::span<double> point_gradients;    ///< 9 per point: F, column-major
  std::span<double> point_stresses;     ///< 9 per point: the stress the tangent is taken with
  std::span<double> pair_arms;          ///< 3 per pair: R_i (rest arm)
  /// 9 per frame: the positive part of P : d2F/dr2, the second derivative of the energy in
  /// the frame's own rotation increment (geometric stiffness only, else zero).
  std::span<double> frame_spins;
};

/// Rotation matrices (column-major) of unit quaternions, and world inertias R J0 R^T.
void update_rotations(const FrameTables& tables, std::span<const double> orientations, std::span<double> rotations,
                      std::span<double> inertias) noexcept;

/// forces -= dW/dq (restoring elastic forces), refreshing the workspace caches; returns the
/// number of points with det F <= 0.
int add_elastic_forces(const FrameTables& tables, const FrameWorkspace& work, std::span<double> forces) noexcept;

/// forces += load_scale times gravity's generalised forces (force and torque on each frame).
void add_gravity(const FrameTables& tables, const FrameWorkspace& work, double load_scale,
                 std::span<double> forces) noexcept;

/// out += scale K p with K the tangent at the cached state.
void add_stiffness_product(const FrameTables& tables, const FrameWorkspace& work, std::span<const double> p,
                           double scale, std::span<double> out) noexcept;

/// out += scale M p with M the lumped mass (diag m, world inertia).
void add_mass_product(const FrameTables& tables, std::span<const double> inertias, std::span<const double> p,
                      double scale, std::span<double> out) noexcept;

/// Adds mass_scale M + stiffness_scale K to the 6x6 frame blocks (36 per frame, column-major)
/// and, when `band` is not empty, to the lower band (column j holds rows j..j+b at
/// j (b + 1) + (i - j), b = tables.half_bandwidth).
void assemble(const FrameTables& tables, const FrameWorkspace& work, std::span<const double> inertias,
              double mass_scale, double stiffness_scale, std::span<double> blocks, std::span<double> band) noexcept;

/// Elastic energy at frames `positions_m` and unit quaternions `orientations`, in joules.
double elastic_energy(const FrameTables& tables, std::span<const double> positions_m,
                      std::span<const double> orientations) noexcept;

}  // namespace nav::detail
