// The mesher on boxes whose faces lie on grid planes (their volume must come out exact, edges
// and corners kept), its
// determinism, its element-count helper and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mesher/test_shapes.hpp"
#include "nav/mesher/implicit_domain.hpp"
#include "nav/mesher/label_volume_domain.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/mesher/surface_domain.hpp"

namespace nav {
namespace {

// Dyadic sizes, so that grid nodes fall exactly on the faces: 8 x 4 x 6 cubes of 1/64 m.
constexpr double kSize_m = 1.0 / 64.0;
const Bounds3 kBox{{0.0, 0.0, 0.0}, {0.125, 0.0625, 0.09375}};
constexpr double kBoxVolume_m3 = 0.125 * 0.0625 * 0.09375;

void expect_exact_box(const MeshingDomain& domain) {
  const auto made = make_tet_mesh(domain, {.element_size_m = kSize_m, .fitting = {}});
  ASSERT_TRUE(made.ok()) << made.error().describe();
  const MesherOutput& out = made.value();
  EXPECT_EQ(out.mesh.tets.size(), 8u * 4u * 6u * 6u);
  // Exact up to the projection's tolerance (1e-10 m): nodes may slide along the faces.
  EXPECT_NEAR(total_volume_m3(out.mesh) / kBoxVolume_m3, 1.0, 1e-9);
  EXPECT_EQ(out.report.quality.inverted, 0u);
  EXPECT_TRUE(out.report.fitting.unsnapped_nodes.empty());
  const Bounds3 box = bounds_of(out.mesh.nodes_m);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(box.min_m[a], kBox.min_m[a], 1e-10);
    EXPECT_NEAR(box.max_m[a], kBox.max_m[a], 1e-10);
  }
}

TEST(MesherBox, ImplicitBoxVolumeIsExact) { expect_exact_box(make_box_domain(kBox)); }

TEST(MesherBox, TriangulatedBoxVolumeIsExact) { expect_exact_box(SurfaceDomain(testing::box_surface(kBox))); }

TEST(MesherDeterminism, SameInputGivesBitwiseSameMesh) {
  const Point3 centre{0.001, 0.002, -0.003};
  const SurfaceDomain surface(testing::icosphere(centre, 0.02, 3));
  const LabelVolumeDomain labels(testing::voxel_ball(centre, 0.02, 0.001));
  for (const MeshingDomain* domain :
       {static_cast<const MeshingDomain*>(&surface), static_cast<const MeshingDomain*>(&labels)}) {
    const MesherOptions options{.element_size_m = 0.003, .fitting = {}};
    const auto first = make_tet_mesh(*domain, options);
    const auto second = make_tet_mesh(*domain, options);
    ASSERT_TRUE(first.ok() && second.ok());
    EXPECT_TRUE(testing::bitwise_equal(first.value().mesh, second.value().mesh));
    EXPECT_EQ(first.value().boundary_nodes, second.value().boundary_nodes);
  }
}

TEST(MesherElementCount, SizeForACountGivesAboutThatCount) {
  constexpr double kRadius_m = 0.03;
  const double volume_m3 = 4.0 / 3.0 * 3.14159265358979 * kRadius_m * kRadius_m * kRadius_m;
  for (const double count : {2000.0, 20000.0}) {
    const auto made = make_tet_mesh(make_ball_domain({0, 0, 0}, kRadius_m),
                                    {.element_size_m = element_size_for_tet_count_m(volume_m3, count), .fitting = {}});
    ASSERT_TRUE(made.ok());
    EXPECT_NEAR(static_cast<double>(made.value().mesh.tets.size()) / count, 1.0, 0.15);
  }
}

TEST(MesherErrors, RejectsBadSizes) {
  const ImplicitDomain ball = make_ball_domain({0, 0, 0}, 0.02);
  for (const double size_m : {0.0, -0.01, std::numeric_limits<double>::quiet_NaN(), 1e-5, 1.0}) {
    const auto made = make_tet_mesh(ball, {.element_size_m = size_m, .fitting = {}});
    ASSERT_FALSE(made.ok()) << size_m;
    EXPECT_EQ(made.error().field, "element_size_m");
  }
}

}  // namespace
}  // namespace nav
