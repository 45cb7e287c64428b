#pragma once
// The full-order linear algebra that a reduction starts from (init time, internal to
// rtlib/nav/reduced): the scene's TetFemModel tables, its rest stiffness over the free dofs,
// the lumped masses, the coupling to the prescribed nodes and the diaphragm lift.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <span>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_fem_tables.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav::detail {

/// A scene's rest system over its free dofs (3 per free node, in TetFemTables::free_nodes order).
struct FullSystem {
  TetFemModel model;                      ///< element tables, masses and supports
  Eigen::SparseMatrix<double> stiffness;  ///< K + Ks over free dofs (both triangles)
  Eigen::VectorXd mass_kg;                ///< lumped mass per free dof
  Eigen::MatrixXd prescribed_coupling;    ///< free dofs x 3: K times a unit move of every prescribed node along x, y, z
};

/// Builds the scene's FullSystem. Errors are those of make_tet_fem_model.
Result<FullSystem> make_full_system(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver);

/// The 3 node_count vector of a free-dof vector (zero at fixed and prescribed nodes).
Eigen::VectorXd expand_free(const TetFemTables& tables, const Eigen::VectorXd& free);

/// The free-dof part of a 3 node_count vector.
Eigen::VectorXd restrict_free(const TetFemTables& tables, std::span<const double> full);

/// The diaphragm lift (3 node_count x 3, column-major): the static response of the free nodes
/// to a unit displacement of every prescribed node along x, y, z, and that unit move at the
/// prescribed nodes. Empty when the scene prescribes no node.
Result<std::vector<double>> diaphragm_lift(const FullSystem& system);

/// The common prescribed displacement of a 3 node_count displacement (that of the first
/// prescribed node; zero without one).
Eigen::Vector3d prescribed_displacement(const TetFemTables& tables, std::span<const double> displacement_m);

}  // namespace nav::detail
