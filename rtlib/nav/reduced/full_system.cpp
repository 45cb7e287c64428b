#include "nav/reduced/full_system.hpp"

#include <vector>

#include "nav/tissue/sparse_cholesky.hpp"
#include "nav/tissue/tet_kernels.hpp"

namespace nav::detail {

Result<FullSystem> make_full_system(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver) {
  // The explicit integrator skips the rest factorisation, which the reduction does not use.
  TissueSolverOptions options = solver;
  options.integrator = Integrator::explicit_central_difference;
  options.rayleigh_stiffness_s = 0.0;
  auto model = make_tet_fem_model(mesh, scene, options);
  if (!model.ok()) return model.error();
  const TetFemTables& tables = model.value().tables();
  const auto free_dofs = static_cast<Eigen::Index>(3 * tables.free_nodes.size());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(tables.tets.size() * 144 + tables.spring_nodes.size() * 3);
  Eigen::MatrixXd coupling = Eigen::MatrixXd::Zero(free_dofs, 3);
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    Matrix43 gradients;
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c) gradients(a, c) = tables.gradients[12 * e + 3 * a + c];
    const Matrix12 ke = element_stiffness(gradients, tables.lame[e], tables.volume_m3[e]);
    for (int a = 0; a < 4; ++a) {
      const std::int32_t fa = tables.free_index[static_cast<std::size_t>(tables.tets[e][a])];
      if (fa < 0) continue;
      for (int b = 0; b < 4; ++b) {
        const auto node_b = static_cast<std::size_t>(tables.tets[e][b]);
        const std::int32_t fb = tables.free_index[node_b];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            if (fb >= 0)
              triplets.emplace_back(3 * fa + i, 3 * fb + j, ke(3 * a + i, 3 * b + j));
            else if (tables.node_kind[node_b] == NodeKind::prescribed)
              coupling(3 * fa + i, j) += ke(3 * a + i, 3 * b + j);
          }
      }
    }
  }
  for (std::int32_t node : tables.spring_nodes) {
    const std::int32_t f = tables.free_index[static_cast<std::size_t>(node)];
    if (f >= 0)
      for (int i = 0; i < 3; ++i) triplets.emplace_back(3 * f + i, 3 * f + i, tables.spring_stiffness_n_m);
  }
  FullSystem system{std::move(model).value(), Eigen::SparseMatrix<double>(free_dofs, free_dofs),
                    Eigen::VectorXd(free_dofs), std::move(coupling)};
  system.stiffness.setFromTriplets(triplets.begin(), triplets.end());
  const TetFemTables& t = system.model.tables();
  for (Eigen::Index i = 0; i < free_dofs; ++i)
    system.mass_kg[i] = t.mass_kg[static_cast<std::size_t>(t.free_nodes[i / 3])];
  return system;
}

Eigen::VectorXd expand_free(const TetFemTables& tables, const Eigen::VectorXd& free) {
  Eigen::VectorXd full = Eigen::VectorXd::Zero(3 * tables.node_count);
  for (std::size_t f = 0; f < tables.free_nodes.size(); ++f)
    for (int c = 0; c < 3; ++c) full[3 * tables.free_nodes[f] + c] = free[static_cast<Eigen::Index>(3 * f) + c];
  return full;
}

Eigen::VectorXd restrict_free(const TetFemTables& tables, std::span<const double> full) {
  Eigen::VectorXd free(static_cast<Eigen::Index>(3 * tables.free_nodes.size()));
  for (std::size_t f = 0; f < tables.free_nodes.size(); ++f)
    for (int c = 0; c < 3; ++c)
      free[static_cast<Eigen::Index>(3 * f) + c] = full[3 * static_cast<std::size_t>(tables.free_nodes[f]) + c];
  return free;
}

Result<std::vector<double>> diaphragm_lift(const FullSystem& system) {
  const TetFemTables& tables = system.model.tables();
  if (tables.prescribed_nodes.empty()) return std::vector<double>{};
  SparseCholesky factor;
  if (!factor.factor(system.stiffness, "stiffness").ok())
    return Error{
        .message = "the stiffness with the supports applied is singular: the lift needs fixed nodes or springs",
        .field = "fixed_nodes"};
  const auto n3 = static_cast<std::size_t>(3 * tables.node_count);
  std::vector<double> lift(3 * n3, 0.0);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd response = factor.solve(Eigen::VectorXd(-system.prescribed_coupling.col(c)));
    const Eigen::VectorXd full = expand_free(tables, response);
    for (std::size_t i = 0; i < n3; ++i) lift[c * n3 + i] = full[static_cast<Eigen::Index>(i)];
    for (std::int32_t node : tables.prescribed_nodes) lift[c * n3 + 3 * static_cast<std::size_t>(node) + c] = 1.0;
  }
  return lift;
}

Eigen::Vector3d prescribed_displacement(const TetFemTables& tables, std::span<const double> displacement_m) {
  if (tables.prescribed_nodes.empty()) return Eigen::Vector3d::Zero();
  const auto node = static_cast<std::size_t>(tables.prescribed_nodes.front());
  return {displacement_m[3 * node], displacement_m[3 * node + 1], displacement_m[3 * node + 2]};
}

}  // namespace nav::detail
