// Init-time construction of a TetFemModel and its data.
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <string>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/tissue/rest_system.hpp"
#include "nav/tissue/tet_fem_kernels.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_kernels.hpp"

namespace nav {
namespace {

using detail::NodeKind;
using detail::TetFemTables;

Status check_options(const TissueSolverOptions& options) {
  if (!(std::isfinite(options.step_s) && options.step_s > 0.0))
    return field_error("the step must be a positive number of seconds", "step_s");
  if (options.cg_iterations < 1) return field_error("at least one CG iteration is needed", "cg_iterations");
  if (!(options.rayleigh_mass_per_s >= 0.0 && std::isfinite(options.rayleigh_mass_per_s)))
    return field_error("Rayleigh damping must be a non-negative number", "rayleigh_mass_per_s");
  if (!(options.rayleigh_stiffness_s >= 0.0 && std::isfinite(options.rayleigh_stiffness_s)))
    return field_error("Rayleigh damping must be a non-negative number", "rayleigh_stiffness_s");
  if (!(options.incompressibility_gain_pa >= 0.0 && std::isfinite(options.incompressibility_gain_pa)))
    return field_error("the incompressibility gain must be a non-negative number of pascals",
                       "incompressibility_gain_pa");
  if (options.incompressibility_gain_pa > 0.0 && options.law != ElementLaw::st_venant_kirchhoff)
    return field_error("the incompressibility penalty belongs to the St Venant-Kirchhoff law",
                       "incompressibility_gain_pa");
  if (options.integrator == Integrator::explicit_central_difference && options.rayleigh_stiffness_s > 0.0)
    return field_error("stiffness-proportional damping is not available to the explicit integrator",
                       "rayleigh_stiffness_s");
  return Done{};
}

Status build_elements(const TetMesh& mesh, const TissueScene& scene, TetFemTables& tables) {
  const std::int64_t n = tables.node_count;
  tables.tets = mesh.tets;
  tables.gradients.resize(12 * mesh.tets.size());
  tables.volume_m3.resize(mesh.tets.size());
  tables.lame.resize(mesh.tets.size());
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    std::array<Point3, 4> corners;
    for (int a = 0; a < 4; ++a) {
      if (mesh.tets[e][a] < 0 || mesh.tets[e][a] >= n)
        return field_error("element " + std::to_string(e) + " refers to node " + std::to_string(mesh.tets[e][a]),
                           "tets");
      corners[a] = mesh.nodes_m[static_cast<std::size_t>(mesh.tets[e][a])];
    }
    const double volume_m3 = signed_tet_volume_m3(corners[0], corners[1], corners[2], corners[3]);
    if (!(volume_m3 > 0.0)) return field_error("element " + std::to_string(e) + " is inverted or flat", "tets");
    const Matrix43 gradients = shape_gradients(corners);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c) tables.gradients[12 * e + 3 * a + c] = gradients(a, c);
    tables.volume_m3[e] = volume_m3;
    tables.lame[e] = lame_parameters(material_of(mesh, e, scene));
  }
  return Done{};
}

Status build_masses(const TetMesh& mesh, const TissueScene& scene, TetFemTables& tables) {
  tables.mass_kg.assign(static_cast<std::size_t>(tables.node_count), 0.0);
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const double share_kg = material_of(mesh, e, scene).density_kg_m3 * tables.volume_m3[e] / 4.0;
    for (std::int32_t node : mesh.tets[e]) tables.mass_kg[static_cast<std::size_t>(node)] += share_kg;
  }
  if (scene.uniform_total_mass_kg < 0.0 || !std::isfinite(scene.uniform_total_mass_kg))
    return field_error("the total mass must be a non-negative number of kilograms", "uniform_total_mass_kg");
  if (scene.uniform_total_mass_kg > 0.0)
    for (double& mass_kg : tables.mass_kg)
      if (mass_kg > 0.0) mass_kg = scene.uniform_total_mass_kg / static_cast<double>(tables.node_count);
  return Done{};
}

Status check_nodes(const std::vector<std::int32_t>& nodes, std::int64_t node_count, const char* field) {
  for (std::int32_t node : nodes)
    if (node < 0 || node >= node_count) return field_error("node " + std::to_string(node) + " is out of range", field);
  return Done{};
}

std::vector<std::int32_t> sorted_unique(std::vector<std::int32_t> nodes) {
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

/// Node kinds and lists. Nodes of no element have no mass and no stiffness: they are fixed.
Status build_supports(const TissueScene& scene, TetFemTables& tables) {
  const std::int64_t n = tables.node_count;
  if (auto s = check_nodes(scene.fixed_nodes, n, "fixed_nodes"); !s) return s;
  if (auto s = check_nodes(scene.prescribed_nodes, n, "prescribed_nodes"); !s) return s;
  if (auto s = check_nodes(scene.spring_nodes, n, "spring_nodes"); !s) return s;
  if (!scene.spring_nodes.empty() && !(scene.spring_stiffness_n_m > 0.0 && std::isfinite(scene.spring_stiffness_n_m)))
    return field_error("springs need a positive stiffness in N/m", "spring_stiffness_n_m");
  if (!(scene.probe_stiffness_n_m >= 0.0 && std::isfinite(scene.probe_stiffness_n_m)))
    return field_error("the probe stiffness must be a non-negative number of N/m", "probe_stiffness_n_m");
  tables.node_kind.assign(static_cast<std::size_t>(n), NodeKind::free);
  for (std::int32_t node : scene.fixed_nodes) tables.node_kind[static_cast<std::size_t>(node)] = NodeKind::fixed;
  for (std::int32_t node : scene.prescribed_nodes) {
    if (tables.node_kind[static_cast<std::size_t>(node)] == NodeKind::fixed)
      return field_error("node " + std::to_string(node) + " is both fixed and prescribed", "prescribed_nodes");
    tables.node_kind[static_cast<std::size_t>(node)] = NodeKind::prescribed;
  }
  for (std::int64_t node = 0; node < n; ++node)
    if (tables.mass_kg[static_cast<std::size_t>(node)] == 0.0)
      tables.node_kind[static_cast<std::size_t>(node)] = NodeKind::fixed;
  tables.free_index.assign(static_cast<std::size_t>(n), -1);
  for (std::int64_t node = 0; node < n; ++node) {
    const NodeKind kind = tables.node_kind[static_cast<std::size_t>(node)];
    if (kind == NodeKind::fixed) tables.fixed_nodes.push_back(static_cast<std::int32_t>(node));
    if (kind == NodeKind::prescribed) tables.prescribed_nodes.push_back(static_cast<std::int32_t>(node));
    if (kind != NodeKind::free) continue;
    tables.free_index[static_cast<std::size_t>(node)] = static_cast<std::int32_t>(tables.free_nodes.size());
    tables.free_nodes.push_back(static_cast<std::int32_t>(node));
  }
  tables.spring_nodes = sorted_unique(scene.spring_nodes);
  tables.spring_stiffness_n_m = scene.spring_stiffness_n_m;
  tables.probe_stiffness_n_m = scene.probe_stiffness_n_m;
  return Done{};
}

Status build_traction(const TetMesh& mesh, const TissueScene& scene, TetFemTables& tables) {
  std::vector<double> area_m2(static_cast<std::size_t>(tables.node_count), 0.0);
  for (const auto& triangle : scene.traction_triangles) {
    for (std::int32_t node : triangle)
      if (node < 0 || node >= tables.node_count)
        return field_error("node " + std::to_string(node) + " is out of range", "traction_triangles");
    const Point3& a = mesh.nodes_m[static_cast<std::size_t>(triangle[0])];
    const double third_m2 = norm(cross(mesh.nodes_m[static_cast<std::size_t>(triangle[1])] - a,
                                       mesh.nodes_m[static_cast<std::size_t>(triangle[2])] - a)) /
                            6.0;
    for (std::int32_t node : triangle) area_m2[static_cast<std::size_t>(node)] += third_m2;
  }
  for (std::int64_t node = 0; node < tables.node_count; ++node)
    if (area_m2[static_cast<std::size_t>(node)] > 0.0) {
      tables.traction_nodes.push_back(static_cast<std::int32_t>(node));
      tables.traction_area_m2.push_back(area_m2[static_cast<std::size_t>(node)]);
    }
  return Done{};
}

Status build_point_force_patches(const TissueScene& scene, TetFemTables& tables) {
  const double own = scene.point_force_own_share;
  if (!(own > 0.0 && own <= 1.0))
    return field_error("the share a point force keeps on its node must be in (0, 1]", "point_force_own_share");
  if (own == 1.0) return Done{};
  std::vector<std::vector<std::int32_t>> neighbours(static_cast<std::size_t>(tables.node_count));
  for (const auto& tet : tables.tets)
    for (std::int32_t a : tet)
      for (std::int32_t b : tet)
        if (a != b) neighbours[static_cast<std::size_t>(a)].push_back(b);
  tables.patch_offsets.push_back(0);
  for (std::int64_t node = 0; node < tables.node_count; ++node) {
    std::vector<std::int32_t>& ring = neighbours[static_cast<std::size_t>(node)];
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    tables.patch_nodes.push_back(static_cast<std::int32_t>(node));
    tables.patch_weights.push_back(ring.empty() ? 1.0 : own);
    for (std::int32_t other : ring) {
      tables.patch_nodes.push_back(other);
      tables.patch_weights.push_back((1.0 - own) / static_cast<double>(ring.size()));
    }
    tables.patch_offsets.push_back(static_cast<std::int32_t>(tables.patch_nodes.size()));
  }
  return Done{};
}

}  // namespace

Result<std::shared_ptr<TetFemTables>> detail::make_tet_fem_tables(const TetMesh& mesh, const TissueScene& scene,
                                                                  const TissueSolverOptions& options) {
  if (auto s = check_options(options); !s) return s.error();
  if (auto s = check_material(scene.default_material, "default_material"); !s) return s.error();
  for (const auto& [region, material] : scene.region_materials)
    if (auto s = check_material(material, "region_materials[" + std::to_string(region) + "]"); !s) return s.error();
  for (double g : scene.gravity_m_s2)
    if (!std::isfinite(g)) return field_error("gravity must be finite", "gravity_m_s2");
  if (mesh.tets.empty()) return field_error("the mesh has no element", "tets");

  auto tables = std::make_shared<TetFemTables>();
  tables->options = options;
  tables->node_count = static_cast<std::int64_t>(mesh.nodes_m.size());
  tables->gravity_m_s2 = scene.gravity_m_s2;
  tables->max_point_forces = scene.max_point_forces;
  tables->rest_m.reserve(3 * mesh.nodes_m.size());
  for (const Point3& p : mesh.nodes_m) tables->rest_m.insert(tables->rest_m.end(), p.begin(), p.end());
  if (auto s = build_elements(mesh, scene, *tables); !s) return s.error();
  if (auto s = build_masses(mesh, scene, *tables); !s) return s.error();
  if (auto s = build_supports(scene, *tables); !s) return s.error();
  if (auto s = build_traction(mesh, scene, *tables); !s) return s.error();
  if (auto s = build_point_force_patches(scene, *tables); !s) return s.error();
  if (scene.probe_stiffness_n_m > 0.0) {
    tables->probe_nodes = extract_boundary(mesh).mesh_node_of_vertex;
    std::sort(tables->probe_nodes.begin(), tables->probe_nodes.end());
  }
  if (tables->free_nodes.empty()) return field_error("every node is fixed or prescribed", "fixed_nodes");
  return tables;
}

Result<TetFemModel> make_tet_fem_model(const TetMesh& mesh, const TissueScene& scene,
                                       const TissueSolverOptions& options) {
  auto tables = detail::make_tet_fem_tables(mesh, scene, options);
  if (!tables.ok()) return tables.error();
  if (auto s = detail::build_rest_system(*tables.value()); !s) return s.error();
  return TetFemModel(std::move(tables).value());
}

Result<TetFemData> make_tet_fem_data(const TetFemModel& model) {
  const TetFemTables& tables = model.tables();
  const auto n3 = static_cast<std::size_t>(3 * tables.node_count);
  const std::size_t free3 = 3 * tables.free_nodes.size();
  const std::size_t e9 = 9 * tables.tets.size();
  ArenaPlan plan;
  for (int k = 0; k < 11; ++k) plan.add<double>(n3);
  const std::size_t stress_count = tables.options.law == ElementLaw::st_venant_kirchhoff ? e9 : 0;
  plan.add<double>(2 * free3).add<double>(e9).add<double>(3 * n3).add<double>(stress_count);
  TetFemData data(Arena("tet_fem_data", plan.bytes()));
  std::span<double>* full[] = {&data.positions_m,
                               &data.velocities_m_s,
                               &data.forces_n,
                               &data.rhs,
                               &data.solution,
                               &data.residual,
                               &data.preconditioned,
                               &data.direction,
                               &data.product,
                               &data.backup_positions_m,
                               &data.backup_velocities_m_s};
  for (std::span<double>* buffer : full) {
    auto carved = data.arena.allocate<double>("node vector", n3);
    if (!carved.ok()) return carved.error();
    *buffer = carved.value();
  }
  auto free_work = data.arena.allocate<double>("free dof work", 2 * free3);
  auto element_rotations = data.arena.allocate<double>("element rotations", e9);
  auto node_rotations = data.arena.allocate<double>("node rotations", 3 * n3);
  if (!free_work.ok()) return free_work.error();
  if (!element_rotations.ok()) return element_rotations.error();
  if (!node_rotations.ok()) return node_rotations.error();
  auto tangent_stresses = data.arena.allocate<double>("tangent stresses", stress_count);
  if (!tangent_stresses.ok()) return tangent_stresses.error();
  data.tangent_stresses = tangent_stresses.value();
  data.free_work = free_work.value();
  data.element_rotations = element_rotations.value();
  data.node_rotations = node_rotations.value();
  std::copy(tables.rest_m.begin(), tables.rest_m.end(), data.positions_m.begin());
  for (std::size_t e = 0; e < tables.tets.size(); ++e)
    for (int d = 0; d < 3; ++d) data.element_rotations[9 * e + 4 * d] = 1.0;
  for (std::int64_t node = 0; node < tables.node_count; ++node)
    for (int d = 0; d < 3; ++d) data.node_rotations[9 * static_cast<std::size_t>(node) + 4 * d] = 1.0;
  return data;
}

std::int64_t TetFemModel::node_count() const { return tables_->node_count; }
std::int64_t TetFemModel::tet_count() const { return static_cast<std::int64_t>(tables_->tets.size()); }
std::int64_t TetFemModel::free_dof_count() const { return 3 * static_cast<std::int64_t>(tables_->free_nodes.size()); }
const TissueSolverOptions& TetFemModel::options() const { return tables_->options; }
double TetFemModel::stable_step_s() const { return tables_->stable_step_s; }
std::int64_t TetFemModel::factor_nonzeros() const { return tables_->factor.factor_nonzeros(); }
std::int64_t TetFemModel::factor_bytes() const { return tables_->factor.memory_bytes(); }
std::span<const double> TetFemModel::rest_positions_m() const { return tables_->rest_m; }
std::span<const double> TetFemModel::nodal_masses_kg() const { return tables_->mass_kg; }

}  // namespace nav
