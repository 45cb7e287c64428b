// Mesh validation read as a specification: exact volumes, quality of known shapes, flags for
// inverted and degenerate elements, surface closedness and orientation, boundary extraction.
#include <gtest/gtest.h>

#include <cmath>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"

namespace {

using nav::Point3;
using nav::TetMesh;
using nav::TriSurface;

const std::vector<Point3> kCubeCorners{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

/// The unit cube as four corner tetrahedra and the regular one they leave (listed last).
TetMesh five_tet_cube() {
  return TetMesh{kCubeCorners, {{0, 1, 3, 4}, {2, 1, 6, 3}, {5, 1, 4, 6}, {7, 3, 6, 4}, {1, 3, 4, 6}}, {}};
}

/// The unit cube as the six tetrahedra around its diagonal from corner 0 to corner 6.
TetMesh six_tet_cube() {
  return TetMesh{
      kCubeCorners, {{0, 1, 2, 6}, {0, 1, 6, 5}, {0, 3, 6, 2}, {0, 3, 7, 6}, {0, 4, 5, 6}, {0, 4, 6, 7}}, {}};
}

/// A regular tetrahedron of edge sqrt(2), positively oriented.
TetMesh regular_tet() { return TetMesh{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}, {{0, 1, 2, 3}}, {}}; }

/// The closed, outward oriented surface of the unit cube (two triangles a face).
TriSurface cube_surface() {
  TriSurface surface{kCubeCorners, {}};
  const std::array<std::array<std::int32_t, 4>, 6> quads{
      {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}}};
  for (const auto& q : quads) {
    surface.triangles.push_back({q[0], q[1], q[2]});
    surface.triangles.push_back({q[0], q[2], q[3]});
  }
  return surface;
}

TEST(TetMeshValidation, UnitCubeInFiveTetrahedraHasVolumeExactlyOne) {
  const auto report = nav::validate_tet_mesh(five_tet_cube());
  EXPECT_EQ(report.volume_m3, 1.0);
  EXPECT_EQ(report.nodes, 8u);
  EXPECT_EQ(report.tetrahedra, 5u);
  EXPECT_EQ(report.inverted, 0u);
  EXPECT_EQ(report.degenerate, 0u);
  EXPECT_TRUE(report.valid());
}

TEST(TetMeshValidation, UnitCubeInSixTetrahedraHasVolumeOneAndRightAngledQuality) {
  const auto report = nav::validate_tet_mesh(six_tet_cube());
  EXPECT_DOUBLE_EQ(report.volume_m3, 1.0);
  EXPECT_TRUE(report.valid());
  // All six are congruent Kuhn tetrahedra, whose dihedral angles are 45, 60 and 90 degrees.
  EXPECT_NEAR(report.min_dihedral_deg, 45.0, 1e-9);
  EXPECT_NEAR(report.min_quality, report.mean_quality, 1e-12);
}

TEST(TetMeshValidation, RegularTetrahedronHasRadiusRatioOneAndDihedralAcosOneThird) {
  const auto report = nav::validate_tet_mesh(regular_tet());
  EXPECT_NEAR(report.min_quality, 1.0, 1e-14);
  EXPECT_NEAR(report.min_dihedral_deg, std::acos(1.0 / 3.0) * 180.0 / 3.14159265358979323846, 1e-12);
  EXPECT_NEAR(report.min_dihedral_deg, 70.528779, 1e-6);
  EXPECT_NEAR(report.volume_m3, 1.0 / 3.0, 1e-15);
}

TEST(TetMeshValidation, ReflectedTetrahedronIsInvertedButKeepsItsQuality) {
  TetMesh mesh = regular_tet();
  std::swap(mesh.tets[0][2], mesh.tets[0][3]);
  const auto report = nav::validate_tet_mesh(mesh);
  EXPECT_EQ(report.inverted, 1u);
  EXPECT_EQ(report.degenerate, 0u);
  EXPECT_LT(report.volume_m3, 0.0);
  EXPECT_NEAR(report.min_quality, 1.0, 1e-14);
  EXPECT_FALSE(report.valid());
}

TEST(TetMeshValidation, FlattenedTetrahedronIsDegenerate) {
  TetMesh mesh = regular_tet();
  mesh.nodes_m[3] = {0.3, 0.3, 0.4};  // on the plane x + y + z = 1 of the other three
  const auto report = nav::validate_tet_mesh(mesh);
  EXPECT_EQ(report.degenerate, 1u);
  EXPECT_LT(report.min_quality, 1e-12);
  EXPECT_LT(report.min_dihedral_deg, 1e-4);
  EXPECT_FALSE(report.valid());
}

TEST(TetMeshValidation, SliverJustAboveAndBelowTheThresholdIsClassifiedByRadiusRatio) {
  // Four points near a square's corners, lifted +-h alternately: a sliver whose ratio falls with h.
  auto sliver = [](double h) { return TetMesh{{{0, 0, -h}, {1, 1, -h}, {1, 0, h}, {0, 1, h}}, {{0, 1, 2, 3}}, {}}; };
  const auto flat = nav::validate_tet_mesh(sliver(0.01));
  const auto fat = nav::validate_tet_mesh(sliver(0.5));
  EXPECT_LT(flat.min_quality, nav::kDegenerateRadiusRatio);
  EXPECT_EQ(flat.degenerate, 1u);
  EXPECT_GT(fat.min_quality, nav::kDegenerateRadiusRatio);
  EXPECT_EQ(fat.degenerate, 0u);
}

TEST(TetMeshValidation, UnreferencedNodesAndOutOfRangeIndicesAreCounted) {
  TetMesh mesh = five_tet_cube();
  mesh.nodes_m.push_back({5, 5, 5});
  mesh.tets.push_back({0, 1, 2, 42});
  mesh.tets.push_back({-1, 1, 2, 99});
  const auto report = nav::validate_tet_mesh(mesh);
  EXPECT_EQ(report.unreferenced_nodes, 1u);
  EXPECT_EQ(report.out_of_range_indices, 3u);
  EXPECT_EQ(report.volume_m3, 1.0);  // the faulty elements are left out
  EXPECT_FALSE(report.valid());
}

TEST(TetMeshValidation, EmptyMeshIsNotValid) {
  const auto report = nav::validate_tet_mesh(TetMesh{});
  EXPECT_EQ(report.min_quality, 0.0);
  EXPECT_FALSE(report.valid());
}

TEST(SurfaceValidation, CubeSurfaceIsClosedOrientedAndEnclosesOne) {
  const auto report = nav::validate_surface(cube_surface());
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.boundary_edges, 0u);
  EXPECT_EQ(report.non_manifold_edges, 0u);
  EXPECT_DOUBLE_EQ(report.enclosed_volume_m3, 1.0);
}

TEST(SurfaceValidation, CubeWithOneFaceRemovedIsOpen) {
  TriSurface surface = cube_surface();
  surface.triangles.erase(surface.triangles.begin(), surface.triangles.begin() + 2);
  const auto report = nav::validate_surface(surface);
  EXPECT_FALSE(report.closed);
  EXPECT_EQ(report.boundary_edges, 4u);
  EXPECT_TRUE(report.consistently_oriented);
}

TEST(SurfaceValidation, FlippedTriangleMakesTheSurfaceInconsistent) {
  TriSurface surface = cube_surface();
  std::swap(surface.triangles[3][1], surface.triangles[3][2]);
  const auto report = nav::validate_surface(surface);
  EXPECT_TRUE(report.closed);
  EXPECT_FALSE(report.consistently_oriented);
  EXPECT_EQ(report.inconsistent_edges, 3u);
}

TEST(SurfaceValidation, ThirdTriangleOnAnEdgeIsNonManifold) {
  TriSurface surface = cube_surface();
  surface.vertices_m.push_back({0.5, 0.5, -1});
  surface.triangles.push_back({0, 1, 8});
  const auto report = nav::validate_surface(surface);
  EXPECT_FALSE(report.closed);
  EXPECT_EQ(report.non_manifold_edges, 1u);
  EXPECT_EQ(report.boundary_edges, 2u);
}

TEST(SurfaceValidation, OutOfRangeIndicesAreCountedNotFollowed) {
  TriSurface surface = cube_surface();
  surface.triangles.push_back({0, 1, 8});
  const auto report = nav::validate_surface(surface);
  EXPECT_EQ(report.out_of_range_indices, 1u);
  EXPECT_FALSE(report.closed);
  EXPECT_EQ(report.enclosed_volume_m3, 0.0);
}

TEST(BoundaryExtraction, BoundaryOfTheCubeMeshesIsItsClosedOutwardSurface) {
  for (const TetMesh& mesh : {five_tet_cube(), six_tet_cube()}) {
    const auto boundary = nav::extract_boundary(mesh);
    EXPECT_EQ(boundary.surface.triangles.size(), 12u);
    EXPECT_EQ(boundary.surface.vertices_m.size(), 8u);
    const auto report = nav::validate_surface(boundary.surface);
    EXPECT_TRUE(report.closed);
    EXPECT_TRUE(report.consistently_oriented);
    EXPECT_DOUBLE_EQ(report.enclosed_volume_m3, 1.0);
  }
}

TEST(BoundaryExtraction, InteriorNodesAreLeftOutAndMappedBack) {
  // Two tetrahedra sharing a face (which is interior), and an unused node among the used ones.
  TetMesh mesh{{{0, 0, 0}, {9, 9, 9}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}, {{0, 2, 3, 4}, {2, 5, 3, 4}}, {}};
  const auto boundary = nav::extract_boundary(mesh);
  EXPECT_EQ(boundary.surface.triangles.size(), 6u);
  EXPECT_EQ(boundary.mesh_node_of_vertex, (std::vector<std::int32_t>{0, 2, 3, 4, 5}));
  for (std::size_t v = 0; v < boundary.surface.vertices_m.size(); ++v) {
    EXPECT_EQ(boundary.surface.vertices_m[v], mesh.nodes_m[boundary.mesh_node_of_vertex[v]]);
  }
  const auto report = nav::validate_surface(boundary.surface);
  EXPECT_TRUE(report.closed);
  EXPECT_NEAR(report.enclosed_volume_m3, nav::total_volume_m3(mesh), 1e-15);
}

}  // namespace
