// Init-time construction of a MassSpringModel and its data.
#include <algorithm>
#include <cmath>
#include <map>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/tissue/mass_spring_model.hpp"
#include "nav/tissue/tet_fem_tables.hpp"

namespace nav {

Result<MassSpringModel> make_mass_spring_model(const TetMesh& mesh, const TissueScene& scene,
                                               const MassSpringOptions& options) {
  if (!(std::isfinite(options.step_s) && options.step_s > 0.0))
    return Error{.message = "the step must be a positive number of seconds", .field = "step_s"};
  if (!(std::isfinite(options.damping_per_s) && options.damping_per_s >= 0.0))
    return Error{.message = "damping must be a non-negative number", .field = "damping_per_s"};
  if (options.volume_newton_iterations < 1)
    return Error{.message = "at least one iteration is needed", .field = "volume_newton_iterations"};
  TissueSolverOptions support_options;
  support_options.integrator = Integrator::explicit_central_difference;
  support_options.rotation = ElementRotation::none;
  support_options.step_s = options.step_s;
  auto supports = make_tet_fem_model(mesh, scene, support_options);
  if (!supports.ok()) return supports.error();
  const detail::TetFemTables& fem = supports.value().tables();

  auto tables =
      std::make_shared<MassSpringTables>(MassSpringTables{options, supports.value(), {}, {}, {}, {}, {}, 0.0, 0.0});
  std::map<std::array<std::int32_t, 2>, double> edge_stiffness;  // ordered: springs come out sorted
  for (std::size_t e = 0; e < fem.tets.size(); ++e) {
    const double modulus_pa = fem.lame[e].mu_pa * (3.0 * fem.lame[e].lambda_pa + 2.0 * fem.lame[e].mu_pa) /
                              (fem.lame[e].lambda_pa + fem.lame[e].mu_pa);
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const std::array<std::int32_t, 2> edge{std::min(fem.tets[e][a], fem.tets[e][b]),
                                               std::max(fem.tets[e][a], fem.tets[e][b])};
        const double length_m =
            norm(mesh.nodes_m[static_cast<std::size_t>(edge[0])] - mesh.nodes_m[static_cast<std::size_t>(edge[1])]);
        edge_stiffness[edge] += modulus_pa * fem.volume_m3[e] / (length_m * length_m);
      }
  }
  std::vector<double> stiffness_sum(static_cast<std::size_t>(fem.node_count), 0.0);
  for (const auto& [edge, stiffness_n_m] : edge_stiffness) {
    tables->springs.push_back(edge);
    tables->stiffness_n_m.push_back(stiffness_n_m);
    tables->rest_length_m.push_back(
        norm(mesh.nodes_m[static_cast<std::size_t>(edge[0])] - mesh.nodes_m[static_cast<std::size_t>(edge[1])]));
    for (std::int32_t node : edge) stiffness_sum[static_cast<std::size_t>(node)] += stiffness_n_m;
  }
  double omega_squared_max = 0.0;  // Gershgorin: row sums of |M^-1 K| are 2 sum k / m
  for (std::int32_t node : fem.free_nodes)
    omega_squared_max = std::max(omega_squared_max, 2.0 * stiffness_sum[static_cast<std::size_t>(node)] /
                                                        fem.mass_kg[static_cast<std::size_t>(node)]);
  tables->stable_step_s = omega_squared_max > 0.0 ? 2.0 / std::sqrt(omega_squared_max) : 0.0;

  const TetMeshBoundary boundary = extract_boundary(mesh);
  tables->constraint_mask.assign(static_cast<std::size_t>(fem.node_count), 0.0);
  for (const auto& triangle : boundary.surface.triangles) {
    std::array<std::int32_t, 3> nodes{};
    for (int a = 0; a < 3; ++a) {
      nodes[a] = boundary.mesh_node_of_vertex[static_cast<std::size_t>(triangle[a])];
      if (fem.free_index[static_cast<std::size_t>(nodes[a])] >= 0)
        tables->constraint_mask[static_cast<std::size_t>(nodes[a])] = 1.0;
    }
    tables->boundary_triangles.push_back(nodes);
  }
  tables->rest_volume_m3 = enclosed_volume_m3(tables->boundary_triangles, fem.rest_m);
  if (!(tables->rest_volume_m3 > 0.0)) return Error{.message = "the boundary encloses no volume", .field = "tets"};
  return MassSpringModel(std::move(tables));
}

Result<MassSpringData> make_mass_spring_data(const MassSpringModel& model) {
  const auto n3 = static_cast<std::size_t>(3 * model.node_count());
  ArenaPlan plan;
  for (int k = 0; k < 6; ++k) plan.add<double>(n3);
  MassSpringData data(Arena("mass_spring_data", plan.bytes()));
  for (std::span<double>* buffer : {&data.positions_m, &data.velocities_m_s, &data.forces_n, &data.volume_gradient,
                                    &data.backup_positions_m, &data.backup_velocities_m_s}) {
    auto carved = data.arena.allocate<double>("node vector", n3);
    if (!carved.ok()) return carved.error();
    *buffer = carved.value();
  }
  const std::span<const double> rest = model.tables().supports.rest_positions_m();
  std::copy(rest.begin(), rest.end(), data.positions_m.begin());
  return data;
}

double enclosed_volume_m3(std::span<const std::array<std::int32_t, 3>> triangles, std::span<const double> x) noexcept {
  double six_volume = 0.0;
  for (const auto& t : triangles) {
    const double* a = x.data() + 3 * static_cast<std::size_t>(t[0]);
    const double* b = x.data() + 3 * static_cast<std::size_t>(t[1]);
    const double* c = x.data() + 3 * static_cast<std::size_t>(t[2]);
    six_volume +=
        a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return six_volume / 6.0;
}

}  // namespace nav
