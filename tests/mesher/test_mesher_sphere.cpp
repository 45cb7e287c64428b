// The mesher against the analytic ball, from its three kinds of domain: volume error shrinking
// with the element size, no inverted element, boundary nodes on the sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "mesher/test_shapes.hpp"
#include "nav/mesher/implicit_domain.hpp"
#include "nav/mesher/label_volume_domain.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/mesher/surface_domain.hpp"

namespace nav {
namespace {

constexpr double kSphereRadius_m = 0.02;
const Point3 kSphereCentre_m{0.0013, -0.0021, 0.0007};
const double kBallVolume_m3 = 4.0 / 3.0 * std::numbers::pi * kSphereRadius_m * kSphereRadius_m * kSphereRadius_m;

/// Meshes `domain` at r/3, r/6 and r/12 and checks every level; `boundary_tolerance_m` is how
/// far from the true sphere the domain's own boundary may lie.
void expect_converging_ball(const MeshingDomain& domain, double boundary_tolerance_m, const char* name) {
  std::vector<double> errors;
  for (const double divisions : {3.0, 6.0, 12.0}) {
    const auto made = make_tet_mesh(domain, {.element_size_m = kSphereRadius_m / divisions, .fitting = {}});
    ASSERT_TRUE(made.ok()) << made.error().describe();
    const MesherOutput& out = made.value();
    const double error = std::abs(total_volume_m3(out.mesh) / kBallVolume_m3 - 1.0);
    errors.push_back(error);
    std::printf(
        "%s h=r/%-2.0f tets=%6zu nodes=%6zu volume error=%.4f%% min ratio=%.3f min dihedral=%.1f deg "
        "unsnapped=%zu max gap=%.2e m\n",
        name, divisions, out.mesh.tets.size(), out.mesh.nodes_m.size(), 100.0 * error, out.report.quality.min_quality,
        out.report.quality.min_dihedral_deg, out.report.fitting.unsnapped_nodes.size(), out.report.fitting.max_gap_m);
    EXPECT_EQ(out.report.quality.inverted, 0u);
    EXPECT_GT(out.report.quality.min_quality, 0.09);  // the guard keeps radius ratios at 0.1 or above
    EXPECT_TRUE(out.report.fitting.unsnapped_nodes.empty());
    EXPECT_LT(testing::max_boundary_distance_from_sphere_m(out.mesh, kSphereCentre_m, kSphereRadius_m),
              boundary_tolerance_m);
  }
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  EXPECT_LT(errors[2], 0.03);
}

TEST(MesherBall, ImplicitFunctionConverges) {
  expect_converging_ball(make_ball_domain(kSphereCentre_m, kSphereRadius_m), 1e-9, "implicit");
}

TEST(MesherBall, TriangulatedIcosphereConverges) {
  // 5120 triangles: the icosphere lies within 3e-5 m (0.15 % of r) of the sphere.
  expect_converging_ball(SurfaceDomain(testing::icosphere(kSphereCentre_m, kSphereRadius_m, 4)), 3e-5, "surface");
}

TEST(MesherBall, VoxelisedLabelVolumeConverges) {
  // 0.5 mm voxels: the 0.5 level of the trilinear indicator lies within half a voxel of the sphere.
  constexpr double kSpacing_m = 0.0005;
  expect_converging_ball(LabelVolumeDomain(testing::voxel_ball(kSphereCentre_m, kSphereRadius_m, kSpacing_m)),
                         0.5 * kSpacing_m, "labels");
}

}  // namespace
}  // namespace nav
