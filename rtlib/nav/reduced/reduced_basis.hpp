#pragma once
// A reduced basis of one tissue mesh and scene: what the offline reduction (navtool reduce)
// produces, what the reduced-model artifact stores, and what the online reduced model is
// built from. Plain data, no Eigen: widely included. Displacements from rest are
// u = basis * q + diaphragm_lift * d, with q the reduced coordinates and d the prescribed
// diaphragm displacement (TissueInputs::prescribed_displacement_m).
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// Where the columns of a basis come from.
enum class ReducedBasisSource : std::uint32_t {
  linear_modes = 0,       ///< vibration modes of K phi = w^2 M phi with the supports applied
  modal_derivatives = 1,  ///< linear modes plus their StVK modal derivatives
  pod = 2,                ///< proper orthogonal decomposition of full-order training snapshots
};

/// How the reduced internal force (and tangent) is evaluated online.
enum class ReducedForceKind : std::uint32_t {
  linear = 0,                 ///< constant reduced stiffness U^T K U
  corotational_cubature = 1,  ///< corotational elements on sampled, weighted tetrahedra
  stvk_cubature = 2,          ///< St Venant-Kirchhoff elements on sampled, weighted tetrahedra
  stvk_cubic_polynomial = 3,  ///< exact reduced St Venant-Kirchhoff: a cubic polynomial in q
};

/// The calibration of a reduced model's online error estimate (error_calibration.hpp): the
/// displacement its basis misses under the point forces (a needle, a probe), from the static
/// compliance it misses about each node, fitted on held-out loads against the full order's
/// largest nodal error. Empty compliance: no estimate.
struct ReducedErrorCalibration {
  /// Per node, 6 values (xx, xy, xz, yy, yz, zz), m/N: the full order's static response to a
  /// unit force spread over the nodes within a patch radius, averaged over them, less the
  /// basis's own (K with the scene's springs); zero at constrained nodes.
  std::vector<double> missing_compliance_m_per_n;
  double gain = 0.0;  ///< estimated error = gain x the sum of |M_n f_n| over loaded nodes
  /// On the held-out loads with point forces: the correlation of the estimate with the true
  /// error, and the range of true / estimated error.
  double correlation = 0.0, lowest_ratio = 0.0, highest_ratio = 0.0;
  int held_out_loads = 0;
};

/// Everything the offline reduction computes for one mesh and scene.
struct ReducedBasis {
  std::uint64_t mesh_fingerprint = 0;  ///< mesh_fingerprint() of the mesh it belongs to
  std::int32_t node_count = 0;
  std::int32_t basis_size = 0;  ///< r
  ReducedBasisSource source = ReducedBasisSource::pod;
  ReducedForceKind force_kind = ReducedForceKind::corotational_cubature;
  /// Column-major (3 node_count) x r, mass-orthonormal; rows of fixed nodes are zero.
  std::vector<double> basis;
  /// Per column: w^2 in 1/s^2 for modes, the captured snapshot energy fraction for POD
  /// (cumulative), 0 where it has no meaning.
  std::vector<double> column_values;
  /// Column-major (3 node_count) x 3: the static response to a unit diaphragm displacement
  /// along x, y, z (empty when the scene prescribes no nodes).
  std::vector<double> diaphragm_lift;
  /// Cubature: sampled tetrahedra and their non-negative weights (same length).
  std::vector<std::int32_t> sample_tets;
  std::vector<double> sample_weights;
  /// stvk_cubic_polynomial only: the polynomial's coefficients, in the layout of the
  /// reduced StVK code (empty otherwise).
  std::vector<double> polynomial_coefficients;
  /// Training envelope: the largest |q_i| met in training, per column (r values), and the
  /// largest relative residual of the reduced equations seen on the training loads.
  std::vector<double> training_q_bound;
  double training_residual_bound = 0.0;
  ReducedErrorCalibration error_calibration;
};

/// A 64-bit fingerprint of a mesh's node coordinates and tetrahedra (FNV-1a over their
/// bytes): two meshes with the same fingerprint are, for a basis, the same mesh.
std::uint64_t mesh_fingerprint(const TetMesh& mesh);

}  // namespace nav
