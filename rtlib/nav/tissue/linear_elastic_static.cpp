#include "nav/tissue/linear_elastic_static.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>

#include "nav/mesh/geometry.hpp"
#include "nav/tissue/sparse_cholesky.hpp"
#include "nav/tissue/tet_kernels.hpp"
#include "nav/tissue/von_mises.hpp"

namespace nav {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

/// The first feature of `scene` or `loads` a linear static solve does not take, as an Error.
Status check_supported(const TissueScene& scene, const TissueInputs& loads) {
  const auto unsupported = [](const char* field) {
    return Error{.message = "not taken by the linear static solve (give it to a tissue model)", .field = field};
  };
  if (!scene.prescribed_nodes.empty()) return unsupported("prescribed_nodes");
  if (!scene.spring_nodes.empty()) return unsupported("spring_nodes");
  if (!scene.traction_triangles.empty()) return unsupported("traction_triangles");
  if (scene.uniform_total_mass_kg > 0.0) return unsupported("uniform_total_mass_kg");
  if (scene.point_force_own_share != 1.0) return unsupported("point_force_own_share");
  if (loads.probe.active) return unsupported("probe");
  return Done{};
}

}  // namespace

Result<StaticSolution> solve_linear_static(const TetMesh& mesh, const TissueScene& scene, const TissueInputs& loads) {
  const auto node_count = static_cast<std::int64_t>(mesh.nodes_m.size());
  if (const Status supported = check_supported(scene, loads); !supported.ok()) return supported.error();
  if (scene.fixed_nodes.empty())
    return Error{.message = "no fixed node: the system has rigid motions", .field = "fixed_nodes"};

  // Free dof numbering: -1 for fixed components.
  std::vector<std::int64_t> dof_index(3 * node_count, 0);
  for (std::int32_t node : scene.fixed_nodes) {
    if (node < 0 || node >= node_count)
      return Error{.message = "node " + std::to_string(node) + " is out of range", .field = "fixed_nodes"};
    for (int c = 0; c < 3; ++c) dof_index[3 * node + c] = -1;
  }
  std::int64_t free_dofs = 0;
  for (auto& index : dof_index)
    if (index == 0) index = free_dofs++;

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(mesh.tets.size() * 144);
  Eigen::VectorXd force = Eigen::VectorXd::Zero(free_dofs);
  std::vector<Matrix6x12> stress_from_displacement(mesh.tets.size());
  std::vector<double> volumes_m3(mesh.tets.size());

  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto& tet = mesh.tets[e];
    std::array<Point3, 4> x;
    for (int a = 0; a < 4; ++a) {
      if (tet[a] < 0 || tet[a] >= node_count)
        return Error{.message = "element " + std::to_string(e) + " refers to node " + std::to_string(tet[a]),
                     .field = "tets"};
      x[a] = mesh.nodes_m[tet[a]];
    }
    const double volume_m3 = signed_tet_volume_m3(x[0], x[1], x[2], x[3]);
    if (!(volume_m3 > 0.0))
      return Error{.message = "element " + std::to_string(e) + " is inverted or flat", .field = "tets"};
    const ElasticMaterial& material = material_of(mesh, e, scene);
    const Matrix43 gradients = shape_gradients(x);
    const LameParameters lame = lame_parameters(material);
    stress_from_displacement[e].noalias() = elasticity_matrix(lame) * strain_displacement(gradients);
    volumes_m3[e] = volume_m3;
    const Matrix12 ke = element_stiffness(gradients, lame, volume_m3);
    const double nodal_mass_kg = material.density_kg_m3 * volume_m3 / 4.0;
    for (int a = 0; a < 4; ++a) {
      for (int i = 0; i < 3; ++i) {
        const std::int64_t row = dof_index[3 * tet[a] + i];
        if (row < 0) continue;
        force[row] += loads.load_scale * nodal_mass_kg * scene.gravity_m_s2[i];
        for (int b_node = 0; b_node < 4; ++b_node)
          for (int j = 0; j < 3; ++j) {
            const std::int64_t col = dof_index[3 * tet[b_node] + j];
            if (col >= 0) triplets.emplace_back(row, col, ke(3 * a + i, 3 * b_node + j));
          }
      }
    }
  }

  for (const PointForce& point : loads.point_forces) {
    if (point.node < 0 || point.node >= node_count)
      return Error{.message = "node " + std::to_string(point.node) + " is out of range", .field = "point_forces"};
    for (int c = 0; c < 3; ++c)
      if (dof_index[3 * point.node + c] >= 0)
        force[dof_index[3 * point.node + c]] += loads.load_scale * point.force_n[c];
  }

  Eigen::SparseMatrix<double> stiffness(free_dofs, free_dofs);
  stiffness.setFromTriplets(triplets.begin(), triplets.end());
  SparseCholesky solver;
  if (!solver.factor(stiffness, "stiffness").ok())
    return Error{.message = "the stiffness matrix could not be factorised", .field = "stiffness"};
  const Eigen::VectorXd u = solver.solve(force);

  StaticSolution solution;
  solution.free_dofs = free_dofs;
  const double force_norm = force.norm();
  solution.relative_residual = force_norm > 0.0 ? (stiffness * u - force).norm() / force_norm : 0.0;
  solution.displacement_m.assign(node_count, Point3{0.0, 0.0, 0.0});
  for (std::int64_t n = 0; n < node_count; ++n)
    for (int c = 0; c < 3; ++c)
      if (dof_index[3 * n + c] >= 0) solution.displacement_m[n][c] = u[dof_index[3 * n + c]];

  solution.von_mises_stress_pa.resize(mesh.tets.size());
  solution.nodal_von_mises_stress_pa.assign(node_count, 0.0);
  std::vector<double> nodal_volume_m3(node_count, 0.0);
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    Eigen::Matrix<double, 12, 1> ue;
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c) ue[3 * a + c] = solution.displacement_m[mesh.tets[e][a]][c];
    const Vector6 voigt = stress_from_displacement[e] * ue;
    const double stress = von_mises_pa(voigt.data());
    solution.von_mises_stress_pa[e] = stress;
    for (int a = 0; a < 4; ++a) {
      solution.nodal_von_mises_stress_pa[mesh.tets[e][a]] += stress * volumes_m3[e];
      nodal_volume_m3[mesh.tets[e][a]] += volumes_m3[e];
    }
  }
  for (std::int64_t n = 0; n < node_count; ++n)
    if (nodal_volume_m3[n] > 0.0) solution.nodal_von_mises_stress_pa[n] /= nodal_volume_m3[n];
  return solution;
}

}  // namespace nav
