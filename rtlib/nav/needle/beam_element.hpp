#pragma once
// One corotational 3-D beam element (Przemieniecki's 12x12 stiffness, Euler-Bernoulli or
// Timoshenko) between two node frames: its local stiffness, and its nodal forces and
// tangent in world axes from the current node positions and rotations.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "nav/needle/needle_parameters.hpp"

namespace nav {

using Matrix12d = Eigen::Matrix<double, 12, 12>;
using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// The local stiffness of a straight element of rest length `length_m`, dof order
/// (u, v, w, theta_x, theta_y, theta_z) of node a then node b, local x along the element.
Matrix12d beam_local_stiffness(const NeedleParameters& parameters, const NeedleSection& section, double length_m);

/// A local stiffness with what the corotational response needs of it worked out once: for
/// each local force its nonzero terms on the freedoms a corotational deformation moves (the
/// node rotations and the stretch), in freedom order; and for each of the ten 3x3 blocks of
/// the tangent the first block with the same coefficients (rotated alike, so rotated once).
struct BeamStiffness {
  /// One nonzero entry of a local force's row.
  struct Term {
    int freedom = 0;
    double value = 0.0;
  };
  static constexpr int kMovedFreedoms = 7;   ///< theta_a (3), the stretch, theta_b (3)
  static constexpr int kTangentBlocks = 10;  ///< aa: 3, ab: 4, bb: 3 (the symmetric ones' lower blocks mirrored)
  Matrix12d local;
  std::array<std::array<Term, kMovedFreedoms>, 12> force_terms{};
  std::array<int, 12> force_term_count{};
  std::array<int, kTangentBlocks> same_block_as{};
};

/// The corotational response's view of `local` (as beam_local_stiffness builds it).
BeamStiffness beam_stiffness(const Matrix12d& local);

/// The two end frames of an element in its current configuration.
struct BeamEnds {
  Eigen::Vector3d position_a_m, position_b_m;
  Eigen::Quaterniond rotation_a, rotation_b;  ///< node frames (x along the shaft at rest)
};

/// Internal forces of an element in world axes: (force_a, moment_a, force_b, moment_b),
/// and its symmetric tangent R K_local R^T (the element rotation held fixed) as its three
/// distinct 6x6 blocks: [[aa, ab], [ab^T, bb]] over (node a, node b).
struct BeamResponse {
  Vector12d forces;
  Matrix6d tangent_aa, tangent_ab, tangent_bb;
};

/// Corotational response: the element frame follows the chord and the mean node frame, the
/// local deformation is the stretch and the node rotations relative to that frame. A rigid
/// motion of both ends gives exactly zero force.
BeamResponse corotational_beam_response(const BeamStiffness& stiffness, double rest_length_m,
                                        const BeamEnds& ends) noexcept;

}  // namespace nav
