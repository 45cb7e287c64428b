#pragma once
// Analytic shapes for the mesher's tests: a triangulated sphere, a voxelised ball, a box
// surface, and the measures that compare a mesh with them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/label_volume.hpp"

namespace nav::testing {

/// An icosahedron around `centre_m` subdivided `levels` times (20 * 4^levels triangles),
/// vertices on the sphere of `radius_m`, triangles counter-clockwise seen from outside.
inline TriSurface icosphere(const Point3& centre_m, double radius_m, int levels) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Point3> unit{{-1, phi, 0},  {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi},  {0, 1, phi},
                           {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1},  {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  std::vector<std::array<std::int32_t, 3>> faces{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Point3& p : unit) p = (1.0 / norm(p)) * p;
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> midpoints;
    const auto midpoint = [&](std::int32_t a, std::int32_t b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      const Point3 m = 0.5 * (unit[a] + unit[b]);
      unit.push_back((1.0 / norm(m)) * m);
      return midpoints[key] = static_cast<std::int32_t>(unit.size() - 1);
    };
    std::vector<std::array<std::int32_t, 3>> finer;
    for (const auto& f : faces) {
      const std::int32_t ab = midpoint(f[0], f[1]);
      const std::int32_t bc = midpoint(f[1], f[2]);
      const std::int32_t ca = midpoint(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  TriSurface surface;
  for (const Point3& p : unit) surface.vertices_m.push_back(centre_m + radius_m * p);
  surface.triangles = std::move(faces);
  return surface;
}

/// A ball of `radius_m` around `centre_m` voxelised at `spacing_m` (label 1 where the voxel
/// centre is inside), with two voxels of background around it.
inline LabelVolume voxel_ball(const Point3& centre_m, double radius_m, double spacing_m) {
  LabelVolume volume;
  const int half = static_cast<int>(std::ceil(radius_m / spacing_m)) + 2;
  volume.size = {2 * half + 1, 2 * half + 1, 2 * half + 1};
  volume.spacing_m = {spacing_m, spacing_m, spacing_m};
  volume.origin_m = centre_m - Point3{half * spacing_m, half * spacing_m, half * spacing_m};
  for (int k = 0; k < volume.size[2]; ++k)
    for (int j = 0; j < volume.size[1]; ++j)
      for (int i = 0; i < volume.size[0]; ++i) {
        const Point3 p = volume.origin_m + Point3{i * spacing_m, j * spacing_m, k * spacing_m};
        volume.labels.push_back(norm(p - centre_m) < radius_m ? 1 : 0);
      }
  return volume;
}

/// The 12 triangles of the surface of an axis-aligned box, outward oriented.
inline TriSurface box_surface(const Bounds3& box) {
  TriSurface surface;
  for (int corner = 0; corner < 8; ++corner) {
    surface.vertices_m.push_back({(corner & 1) ? box.max_m[0] : box.min_m[0],
                                  (corner & 2) ? box.max_m[1] : box.min_m[1],
                                  (corner & 4) ? box.max_m[2] : box.min_m[2]});
  }
  surface.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                       {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return surface;
}

/// Largest | |p - centre| - radius | over the boundary nodes of `mesh`.
inline double max_boundary_distance_from_sphere_m(const TetMesh& mesh, const Point3& centre_m, double radius_m) {
  double worst = 0.0;
  for (const std::int32_t n : extract_boundary(mesh).mesh_node_of_vertex) {
    worst = std::max(worst, std::abs(norm(mesh.nodes_m[n] - centre_m) - radius_m));
  }
  return worst;
}

/// True if the two meshes are bitwise identical.
inline bool bitwise_equal(const TetMesh& a, const TetMesh& b) {
  return a.nodes_m.size() == b.nodes_m.size() && a.tets == b.tets && a.tet_regions == b.tet_regions &&
         std::equal(a.nodes_m.begin(), a.nodes_m.end(), b.nodes_m.begin(), [](const Point3& p, const Point3& q) {
           return std::memcmp(p.data(), q.data(), sizeof(Point3)) == 0;
         });
}

}  // namespace nav::testing
