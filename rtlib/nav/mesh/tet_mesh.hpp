#pragma once
// Init-time mesh containers shared by loaders, the mesher, validation and models.
// Coordinates are in metres. These are built once and then read by models' init code;
// nothing here is touched by step-time code.
#include <array>
#include <cstdint>
#include <vector>

namespace nav {

/// A point or vector in 3-D space, in metres unless the name says otherwise. A type of nav's
/// own (an std::array underneath), so that its operators (geometry.hpp) are found from user
/// code without a using-declaration.
struct Point3 : std::array<double, 3> {};

/// Region tags carried per tetrahedron.
enum class TissueRegion : std::uint8_t { parenchyma = 1, tumour = 2 };

/// A linear tetrahedral mesh: node positions in metres and 4 node indices per element.
/// A positively oriented element has (p1-p0)·((p2-p0)×(p3-p0)) > 0.
struct TetMesh {
  std::vector<Point3> nodes_m;
  std::vector<std::array<std::int32_t, 4>> tets;
  /// One tag per tetrahedron (TissueRegion values, or the file's own region ids);
  /// empty when the source has none.
  std::vector<std::int32_t> tet_regions;
};

/// A triangulated surface: vertex positions in metres and 3 vertex indices per triangle.
/// A closed, outward oriented surface has counter-clockwise triangles seen from outside.
struct TriSurface {
  std::vector<Point3> vertices_m;
  std::vector<std::array<std::int32_t, 3>> triangles;
};

}  // namespace nav
