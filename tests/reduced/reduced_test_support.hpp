#pragma once
// Shared inputs of the reduced-model tests: small beams held at one end, M-inner products of
// basis columns, and snapshot sets from full-order runs.
#include <Eigen/Dense>
#include <span>
#include <vector>

#include "nav/reduced/reduced_basis.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav::testing {

/// A beam [0, length] x [0, width] x [0, height] held at x = 0, E 5 kPa, nu 0.3, 1000 kg/m^3.
struct BeamScene {
  TetMesh mesh;
  TissueScene scene;
  BeamScene(const Point3& size_m, double element_size_m) : mesh(box_mesh(size_m, element_size_m)) {
    scene.default_material = {5.0e3, 0.3, 1000.0};
    scene.fixed_nodes = nodes_where(mesh, 0, 0.0);
  }
};

/// Column j of a basis as an Eigen vector.
inline Eigen::Map<const Eigen::VectorXd> basis_column(const ReducedBasis& basis, int j) {
  const auto n3 = static_cast<Eigen::Index>(3 * basis.node_count);
  return Eigen::Map<const Eigen::VectorXd>(basis.basis.data() + j * n3, n3);
}

/// The basis as a 3n x r matrix.
inline Eigen::MatrixXd basis_matrix(const ReducedBasis& basis) {
  return Eigen::Map<const Eigen::MatrixXd>(basis.basis.data(), 3 * basis.node_count, basis.basis_size);
}

/// Lumped masses repeated per dof (3 node_count).
inline Eigen::VectorXd dof_masses(const TetFemModel& model) {
  Eigen::VectorXd mass(3 * model.node_count());
  for (Eigen::Index i = 0; i < mass.size(); ++i) mass[i] = model.nodal_masses_kg()[static_cast<std::size_t>(i / 3)];
  return mass;
}

/// Displacement snapshots (3 node_count each, column-major) of a full-order model: every
/// `every` steps of `steps` quasi-static steps under inputs(step).
template <class Inputs>
std::vector<double> full_order_snapshots(const TetFemModel& model, int steps, int every, Inputs&& inputs) {
  auto data = make_tet_fem_data(model).value();
  std::vector<double> snapshots;
  const auto rest = model.rest_positions_m();
  for (int i = 0; i < steps; ++i) {
    step(model, data, inputs(i));
    if ((i + 1) % every != 0) continue;
    for (std::size_t k = 0; k < rest.size(); ++k) snapshots.push_back(data.positions_m[k] - rest[k]);
  }
  return snapshots;
}

/// snapshot_count snapshots of `model` (quasi-static) pressed by `force`, taken every second
/// step of a load ramp growing by scale_per_step a step.
inline std::vector<double> ramp_snapshots(const TetFemModel& model, const PointForce& force, int snapshot_count,
                                          double scale_per_step) {
  return full_order_snapshots(model, 2 * snapshot_count, 2, [&](int i) {
    TissueInputs inputs;
    inputs.load_scale = scale_per_step * (i + 1);
    inputs.point_forces = std::span<const PointForce>(&force, 1);
    return inputs;
  });
}

}  // namespace nav::testing
