// The closed-surface domain: crossing parity robust to lines through vertices and edges, and
// exact closest points through the bucket grid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mesher/test_shapes.hpp"
#include "nav/mesher/closest_point.hpp"
#include "nav/mesher/surface_domain.hpp"
#include "nav/mesher/surface_ray_caster.hpp"

namespace nav {
namespace {

/// The regular octahedron |x| + |y| + |z| <= 1: lines on the z axis pass through two
/// vertices where four triangles meet; lines in the planes x = 0 or y = 0 run along edges.
TriSurface octahedron() {
  TriSurface surface;
  surface.vertices_m = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  surface.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return surface;
}

TEST(SurfaceRayCaster, LineThroughTwoVerticesCrossesTwice) {
  std::vector<double> z;
  SurfaceRayCaster(octahedron()).crossings_z(0.0, 0.0, z);
  ASSERT_EQ(z.size(), 2u);
  EXPECT_DOUBLE_EQ(z[0], -1.0);
  EXPECT_DOUBLE_EQ(z[1], 1.0);
}

TEST(SurfaceRayCaster, LinesAlongEdgesCrossTwice) {
  const SurfaceRayCaster rays(octahedron());
  for (const auto& [x, y] :
       std::vector<std::pair<double, double>>{{0.25, 0.0}, {-0.5, 0.0}, {0.0, 0.75}, {0.0, -0.25}}) {
    std::vector<double> z;
    rays.crossings_z(x, y, z);
    ASSERT_EQ(z.size(), 2u) << x << ", " << y;
    EXPECT_NEAR(z[1], 1.0 - std::abs(x) - std::abs(y), 1e-15);
    EXPECT_NEAR(z[0], -z[1], 1e-15);
  }
}

TEST(SurfaceRayCaster, LinesThroughSilhouetteOrOutsideCrossEvenly) {
  const SurfaceRayCaster rays(octahedron());
  std::vector<double> z;
  rays.crossings_z(1.0, 0.0, z);  // through the silhouette vertex (1, 0, 0)
  EXPECT_EQ(z.size() % 2, 0u);
  rays.crossings_z(0.5, 0.5, z);  // along the silhouette edge
  EXPECT_EQ(z.size() % 2, 0u);
  rays.crossings_z(2.0, 0.0, z);
  EXPECT_TRUE(z.empty());
}

TEST(SurfaceDomain, ColumnsAgreeWithPointTests) {
  const SurfaceDomain domain(octahedron());
  std::vector<std::uint8_t> column(41);
  for (const double x : {0.0, 0.25, -0.5, 0.3}) {
    for (const double y : {0.0, 0.5, -0.1}) {
      domain.classify_column(x, y, -1.0, 0.05, column);
      for (std::size_t k = 0; k < column.size(); ++k) {
        const double z = -1.0 + 0.05 * static_cast<double>(k);
        const double l1 = std::abs(x) + std::abs(y) + std::abs(z);
        if (std::abs(l1 - 1.0) < 1e-12) continue;  // on the surface: either answer
        EXPECT_EQ(column[k] != 0, l1 < 1.0) << x << " " << y << " " << z;
        EXPECT_EQ(domain.contains({x, y, z}), l1 < 1.0);
      }
    }
  }
}

TEST(SurfaceDomain, BoxWithGridAlignedFacesAndDiagonalEdges) {
  // Lines through the face diagonals of the box's triangles still count one crossing per face.
  const SurfaceDomain domain(testing::box_surface({{0, 0, 0}, {1, 1, 1}}));
  std::vector<std::uint8_t> column(5);
  domain.classify_column(0.5, 0.5, -0.25, 0.375, column);  // z = -0.25, 0.125, ... 1.25
  EXPECT_EQ(column, (std::vector<std::uint8_t>{0, 1, 1, 1, 0}));
  domain.classify_column(0.25, 0.75, -0.25, 0.375, column);
  EXPECT_EQ(column, (std::vector<std::uint8_t>{0, 1, 1, 1, 0}));
}

TEST(ClosestPoint, OnTriangleRegions) {
  const Point3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_EQ(closest_point_on_triangle({0.2, 0.3, 5.0}, a, b, c), (Point3{0.2, 0.3, 0.0}));   // face
  EXPECT_EQ(closest_point_on_triangle({0.5, -2.0, 1.0}, a, b, c), (Point3{0.5, 0.0, 0.0}));  // edge
  EXPECT_EQ(closest_point_on_triangle({-1.0, -1.0, 0.0}, a, b, c), a);                       // vertex
  EXPECT_EQ(closest_point_on_triangle({3.0, 0.5, 0.0}, a, b, b), b);                         // degenerate
}

TEST(SurfaceDomain, ClosestPointMatchesBruteForce) {
  const TriSurface sphere = testing::icosphere({0.01, 0.0, -0.02}, 0.05, 3);
  const SurfaceDomain domain(sphere);
  for (int i = 0; i < 200; ++i) {
    // Points inside, near and far outside, spread by an irrational rotation.
    const double t = 0.618033988749895 * i;
    const Point3 p{0.12 * std::sin(7.0 * t), 0.09 * std::cos(5.0 * t), 0.1 * std::sin(3.0 * t + 1.0)};
    double best = std::numeric_limits<double>::infinity();
    for (const auto& tri : sphere.triangles) {
      const Point3 q =
          closest_point_on_triangle(p, sphere.vertices_m[tri[0]], sphere.vertices_m[tri[1]], sphere.vertices_m[tri[2]]);
      best = std::min(best, norm(q - p));
    }
    EXPECT_NEAR(norm(domain.project_to_boundary(p) - p), best, 1e-15) << i;
  }
}

}  // namespace
}  // namespace nav
