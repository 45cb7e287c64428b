#include "nav/mesh/validation.hpp"

#include <algorithm>
#include <limits>

#include "nav/mesh/geometry.hpp"

namespace nav {
namespace {

/// Number of indices of `element` outside [0, count).
template <std::size_t corners>
std::size_t indices_out_of_range(const std::array<std::int32_t, corners>& element, std::size_t count) {
  return static_cast<std::size_t>(std::count_if(element.begin(), element.end(), [count](std::int32_t index) {
    return index < 0 || static_cast<std::size_t>(index) >= count;
  }));
}

/// One triangle's use of an edge: its end points in increasing order and whether the triangle
/// runs from low to high.
struct EdgeUse {
  std::int32_t low = 0;
  std::int32_t high = 0;
  bool forward = false;
};

/// A tetrahedron's face: its sorted corners (to find its twin) and its outward ordering.
struct TetFace {
  std::array<std::int32_t, 3> key{};
  std::array<std::int32_t, 3> oriented{};
};

std::vector<TetFace> faces_of_valid_tets(const TetMesh& mesh) {
  std::vector<TetFace> faces;
  faces.reserve(4 * mesh.tets.size());
  for (const auto& tet : mesh.tets) {
    if (indices_out_of_range(tet, mesh.nodes_m.size()) > 0) continue;
    for (const auto& local : kTetFaces) {
      TetFace face;
      face.oriented = {tet[local[0]], tet[local[1]], tet[local[2]]};
      face.key = face.oriented;
      std::sort(face.key.begin(), face.key.end());
      faces.push_back(face);
    }
  }
  std::sort(faces.begin(), faces.end(), [](const TetFace& x, const TetFace& y) { return x.key < y.key; });
  return faces;
}

}  // namespace

bool TetMeshReport::valid() const {
  return tetrahedra > 0 && inverted == 0 && degenerate == 0 && out_of_range_indices == 0 && unreferenced_nodes == 0;
}

TetMeshReport validate_tet_mesh(const TetMesh& mesh, double degenerate_radius_ratio) {
  TetMeshReport report;
  report.nodes = mesh.nodes_m.size();
  report.tetrahedra = mesh.tets.size();
  report.degenerate_radius_ratio = degenerate_radius_ratio;
  std::vector<bool> used(mesh.nodes_m.size(), false);
  double quality_sum = 0.0;
  std::size_t measured = 0;
  report.min_quality = std::numeric_limits<double>::infinity();
  report.min_dihedral_deg = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto& tet = mesh.tets[e];
    const std::size_t bad = indices_out_of_range(tet, mesh.nodes_m.size());
    report.out_of_range_indices += bad;
    if (bad > 0) continue;
    for (const std::int32_t node : tet) used[static_cast<std::size_t>(node)] = true;
    const Point3& a = mesh.nodes_m[tet[0]];
    const Point3& b = mesh.nodes_m[tet[1]];
    const Point3& c = mesh.nodes_m[tet[2]];
    const Point3& d = mesh.nodes_m[tet[3]];
    const double volume_m3 = signed_tet_volume_m3(a, b, c, d);
    const double quality = tet_radius_ratio(a, b, c, d);
    report.volume_m3 += volume_m3;
    report.inverted += volume_m3 <= 0.0 ? 1 : 0;
    report.degenerate += quality < degenerate_radius_ratio ? 1 : 0;
    report.min_quality = std::min(report.min_quality, quality);
    report.min_dihedral_deg = std::min(report.min_dihedral_deg, tet_min_dihedral_deg(a, b, c, d));
    quality_sum += quality;
    ++measured;
  }
  if (measured == 0) {
    report.min_quality = 0.0;
    report.min_dihedral_deg = 0.0;
  } else {
    report.mean_quality = quality_sum / static_cast<double>(measured);
  }
  report.unreferenced_nodes = static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
  return report;
}

SurfaceReport validate_surface(const TriSurface& surface) {
  SurfaceReport report;
  report.vertices = surface.vertices_m.size();
  report.triangles = surface.triangles.size();
  std::vector<EdgeUse> uses;
  uses.reserve(3 * surface.triangles.size());
  for (const auto& triangle : surface.triangles) {
    const std::size_t bad = indices_out_of_range(triangle, surface.vertices_m.size());
    report.out_of_range_indices += bad;
    if (bad > 0) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::int32_t from = triangle[k];
      const std::int32_t to = triangle[(k + 1) % 3];
      uses.push_back({std::min(from, to), std::max(from, to), from < to});
    }
  }
  std::sort(uses.begin(), uses.end(),
            [](const EdgeUse& x, const EdgeUse& y) { return x.low != y.low ? x.low < y.low : x.high < y.high; });
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t last = first + 1;
    while (last < uses.size() && uses[last].low == uses[first].low && uses[last].high == uses[first].high) ++last;
    const std::size_t count = last - first;
    report.boundary_edges += count == 1 ? 1 : 0;
    report.non_manifold_edges += count > 2 ? 1 : 0;
    report.inconsistent_edges += count == 2 && uses[first].forward == uses[first + 1].forward ? 1 : 0;
    first = last;
  }
  const bool indices_ok = report.out_of_range_indices == 0;
  report.closed = indices_ok && report.triangles > 0 && report.boundary_edges == 0 && report.non_manifold_edges == 0;
  report.consistently_oriented = indices_ok && report.triangles > 0 && report.inconsistent_edges == 0;
  report.enclosed_volume_m3 = indices_ok ? enclosed_volume_m3(surface) : 0.0;
  return report;
}

TetMeshBoundary extract_boundary(const TetMesh& mesh) {
  const std::vector<TetFace> faces = faces_of_valid_tets(mesh);
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::vector<std::int32_t> vertex_of_node(mesh.nodes_m.size(), -1);
  for (std::size_t first = 0; first < faces.size();) {
    std::size_t last = first + 1;
    while (last < faces.size() && faces[last].key == faces[first].key) ++last;
    if (last - first == 1) {
      triangles.push_back(faces[first].oriented);
      for (const std::int32_t node : faces[first].oriented) vertex_of_node[static_cast<std::size_t>(node)] = 0;
    }
    first = last;
  }
  TetMeshBoundary boundary;
  for (std::size_t node = 0; node < vertex_of_node.size(); ++node) {
    if (vertex_of_node[node] < 0) continue;
    vertex_of_node[node] = static_cast<std::int32_t>(boundary.mesh_node_of_vertex.size());
    boundary.mesh_node_of_vertex.push_back(static_cast<std::int32_t>(node));
    boundary.surface.vertices_m.push_back(mesh.nodes_m[node]);
  }
  for (auto& triangle : triangles) {
    for (std::int32_t& corner : triangle) corner = vertex_of_node[static_cast<std::size_t>(corner)];
  }
  boundary.surface.triangles = std::move(triangles);
  return boundary;
}

}  // namespace nav
