#include "nav/tissue/liver_scenes.hpp"

#include <algorithm>
#include <utility>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/mesher/surface_domain.hpp"

namespace nav {
namespace {

/// The `count` nodes of `among` nearest `centre`, ascending.
std::vector<std::int32_t> nearest_nodes(const TetMesh& mesh, const Point3& centre, std::size_t count,
                                        const std::vector<std::int32_t>& among) {
  std::vector<std::pair<double, std::int32_t>> by_distance;
  for (std::int32_t n : among) by_distance.emplace_back(norm(mesh.nodes_m[static_cast<std::size_t>(n)] - centre), n);
  std::sort(by_distance.begin(), by_distance.end());
  std::vector<std::int32_t> nodes;
  for (std::size_t k = 0; k < std::min(count, by_distance.size()); ++k) nodes.push_back(by_distance[k].second);
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

}  // namespace

Result<TetMesh> load_liver_mesh(const std::string& liver_dir, int tet_count) {
  if (tet_count >= 20000) return load_tet_mesh(liver_dir + "/liverFine.vtu", LengthUnit::centimetre);
  auto surface = load_surface(liver_dir + "/liver-smoothUV.obj", LengthUnit::centimetre);
  if (!surface.ok()) return surface.error();
  MesherOptions options;
  options.element_size_m = element_size_for_tet_count_m(enclosed_volume_m3(surface.value()), tet_count);
  auto meshed = make_tet_mesh(SurfaceDomain(surface.value()), options);
  if (!meshed.ok()) return meshed.error();
  return std::move(meshed.value().mesh);
}

std::vector<LiverScene> liver_scenes(const TetMesh& mesh) {
  TissueScene base;
  base.default_material = {5000.0, 0.45, 1060.0};
  std::vector<std::int32_t> all(mesh.nodes_m.size());
  for (std::size_t n = 0; n < all.size(); ++n) all[n] = static_cast<std::int32_t>(n);
  for (std::int32_t n : all) {
    const Point3& p = mesh.nodes_m[static_cast<std::size_t>(n)];
    if (p[0] >= 0.0 && p[0] <= 0.02 && p[1] >= 0.03 && p[1] <= 0.05 && p[2] >= -0.01 && p[2] <= 0.02)
      base.fixed_nodes.push_back(n);
  }
  if (base.fixed_nodes.size() < 20) base.fixed_nodes = nearest_nodes(mesh, kLiverHeldCentreM, 20, all);
  LiverScene gravity{"gravity", base, {}};
  gravity.scene.gravity_m_s2 = {0.0, -9.81, 0.0};

  const std::vector<std::int32_t> surface = extract_boundary(mesh).mesh_node_of_vertex;
  const auto distance_to = [&](std::int32_t node, const Point3& p) {
    return norm(mesh.nodes_m[static_cast<std::size_t>(node)] - p);
  };
  std::int32_t tip = surface.front();
  for (std::int32_t n : surface)
    if (distance_to(n, kLiverHeldCentreM) > distance_to(tip, kLiverHeldCentreM)) tip = n;
  const Point3 tip_m = mesh.nodes_m[static_cast<std::size_t>(tip)];
  const Point3 towards = kLiverHeldCentreM - tip_m;
  LiverScene probe{"probe_2cm", base, {}};
  probe.scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  for (std::int32_t n : surface)
    if (distance_to(n, tip_m) < 0.01) probe.scene.prescribed_nodes.push_back(n);
  std::sort(probe.scene.prescribed_nodes.begin(), probe.scene.prescribed_nodes.end());
  probe.inputs.prescribed_displacement_m = (0.02 / norm(towards)) * towards;
  return {gravity, probe};
}

}  // namespace nav
