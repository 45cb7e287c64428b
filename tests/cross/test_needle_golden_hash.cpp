// Same inputs, same bits on every architecture, for the needle: an insertion through two
// layers with shaft friction while the base swings sideways (bending, puncture, cutting,
// the path constraints and the Gauss-Seidel solve all take part), hashed and compared with
// the value recorded on x86_64. The aarch64 build under qemu must reproduce it exactly; the
// reasons it can are those of test_tissue_golden_hash.cpp, and the needle's rotations use
// sin, cos and atan2 of glibc, whose results agree on both (checked by this test).
// The same insertion against surfaces of a mesh (a block's boundary, then the boundary of
// its deeper part), whose hierarchy's nearest-point queries and pseudo-normals take part.
// A deliberate change to the needle numerics changes the value: record the new one from this
// test's output on x86_64, and check that aarch64 agrees.
#include <gtest/gtest.h>

#include <cinttypes>
#include <cstdio>

#include "nav/needle/tissue_surface.hpp"
#include "needle/needle_insertion_support.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

/// The hash of the needle's state after 1500 steps of insertion along +x (20 um each) while
/// the base swings sideways out and back (from arithmetic alone), `z_m` off the axis; both
/// layers punctured.
std::uint64_t swinging_insertion_hash(const NeedleTissueModel& model, double z_m) {
  NeedleTissueData data = make_needle_tissue_data(model, {}).value();
  NeedleTissueInputs inputs;
  for (int i = 0; i < 1500; ++i) {
    const double swing = i < 750 ? i : 1500 - i;
    inputs.needle.base.position_m = {2e-5 * i, 2e-6 * swing, z_m};
    step(model, data, inputs);
  }
  EXPECT_EQ(data.report.punctures, 2);
  const std::uint64_t hash = testing::bits_hash(
      {data.needle.positions_m, data.needle.rotations_wxyz, data.needle.velocities_m_s, data.row_forces});
  std::printf("needle state hash after 1500 steps: 0x%016" PRIx64 "\n", hash);
  return hash;
}

TEST(NeedleGoldenHash, InsertionThroughTwoLayersWithASwingingBase) {
  NeedleTissueScene scene;
  scene.layers = {testing::facing_layer(0.155, 1.0, 0.3, 20.0), testing::facing_layer(0.17, 2.0, 0.5, 40.0)};
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, scene).value();
  EXPECT_EQ(swinging_insertion_hash(model, 0.0), 0x338d4f12fc92e10dULL);
}

TEST(NeedleGoldenHash, InsertionThroughTwoSurfacesOfAMeshWithASwingingBase) {
  // A 10 cm block from x = 0.155 m (2 cm elements), its elements beyond x = 0.175 m tagged 2.
  TetMesh block = testing::box_mesh({0.1, 0.1, 0.1}, 0.02);
  for (Point3& p : block.nodes_m) p = {p[0] + 0.155, p[1] - 0.05, p[2] - 0.05};
  for (const auto& tet : block.tets) {
    double x = 0.0;
    for (const std::int32_t node : tet) x += 0.25 * block.nodes_m[static_cast<std::size_t>(node)][0];
    block.tet_regions.push_back(x > 0.175 ? 2 : 1);
  }
  std::vector<double> rest_m;
  for (const Point3& p : block.nodes_m) rest_m.insert(rest_m.end(), p.begin(), p.end());
  NeedleTissueScene scene;
  scene.surfaces = {mesh_boundary_surface(block), region_boundary_surface(block, 2).value()};
  scene.layers = {testing::facing_layer(0.155, 1.0, 0.3, 20.0), testing::facing_layer(0.175, 2.0, 0.5, 40.0)};
  scene.layers[0].surface = 0;
  scene.layers[1].surface = 1;
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, scene, rest_m).value();
  EXPECT_EQ(swinging_insertion_hash(model, 1e-3), 0x86cfb3be418ddb41ULL);
}

}  // namespace
}  // namespace nav
