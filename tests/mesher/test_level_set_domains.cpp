// Implicit and label-volume domains: inside tests, the distance map, and projection onto the
// boundary level.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "mesher/test_shapes.hpp"
#include "nav/mesher/distance_transform.hpp"
#include "nav/mesher/implicit_domain.hpp"
#include "nav/mesher/label_volume_domain.hpp"

namespace nav {
namespace {

const Point3 kCentre_m{0.003, -0.001, 0.002};
constexpr double kRadius_m = 0.015;

TEST(ImplicitDomain, BallProjectsRadially) {
  const ImplicitDomain ball = make_ball_domain(kCentre_m, kRadius_m);
  EXPECT_TRUE(ball.contains(kCentre_m));
  EXPECT_FALSE(ball.contains(kCentre_m + Point3{0.0, 0.0, 0.016}));
  for (const Point3& offset : {Point3{0.02, 0.0, 0.0}, Point3{0.0, -0.005, 0.0}, Point3{0.007, 0.008, -0.009}}) {
    const Point3 q = ball.project_to_boundary(kCentre_m + offset);
    EXPECT_NEAR(norm(q - kCentre_m), kRadius_m, 1e-10);
    EXPECT_NEAR(norm(cross(q - kCentre_m, offset)), 0.0, 1e-10);  // along the radius
  }
}

TEST(ImplicitDomain, BoxIsASignedDistance) {
  const ImplicitDomain box = make_box_domain({{0.0, 0.0, 0.0}, {0.04, 0.02, 0.01}});
  EXPECT_NEAR(box.value({0.02, 0.01, 0.005}), -0.005, 1e-15);
  EXPECT_NEAR(box.value({0.05, 0.01, 0.005}), 0.01, 1e-15);
  EXPECT_NEAR(box.value({0.05, 0.03, 0.005}), std::sqrt(2.0) * 0.01, 1e-15);
  const Point3 q = box.project_to_boundary({0.02, 0.018, 0.005});  // nearest face: y = 0.02
  EXPECT_NEAR(q[1], 0.02, 1e-10);
  EXPECT_NEAR(q[0], 0.02, 1e-10);
}

TEST(DistanceTransform, MatchesBruteForce) {
  const std::array<std::int64_t, 3> size{7, 6, 5};
  const Point3 spacing{1.0, 2.0, 0.5};
  std::vector<std::uint8_t> inside(7 * 6 * 5, 0);
  const auto index = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return i + 7 * (j + 6 * k); };
  inside[index(3, 2, 2)] = inside[index(4, 2, 2)] = inside[index(3, 3, 2)] = inside[index(1, 5, 0)] = 1;
  const std::vector<float> distance = signed_distance_map_m(inside, size, spacing);
  for (std::int64_t k = 0; k < 5; ++k)
    for (std::int64_t j = 0; j < 6; ++j)
      for (std::int64_t i = 0; i < 7; ++i) {
        double best = 1e300;
        for (std::int64_t c = 0; c < 5; ++c)
          for (std::int64_t b = 0; b < 6; ++b)
            for (std::int64_t a = 0; a < 7; ++a) {
              if (inside[index(a, b, c)] == inside[index(i, j, k)]) continue;
              best = std::min(best, norm({(a - i) * spacing[0], (b - j) * spacing[1], (c - k) * spacing[2]}));
            }
        const double expected = inside[index(i, j, k)] ? -best : best;
        EXPECT_NEAR(distance[index(i, j, k)], expected, 1e-5) << i << " " << j << " " << k;
      }
}

TEST(LabelVolumeDomain, IndicatorIsTrilinear) {
  const LabelVolumeDomain domain(testing::voxel_ball(kCentre_m, kRadius_m, 0.001));
  EXPECT_DOUBLE_EQ(domain.value(kCentre_m), -0.5);
  EXPECT_DOUBLE_EQ(domain.value(kCentre_m + Point3{0.0, 0.0, 0.03}), 0.5);
  EXPECT_TRUE(domain.contains(kCentre_m + Point3{0.0, 0.0, 0.0144}));
  EXPECT_FALSE(domain.contains(kCentre_m + Point3{0.0, 0.0, 0.0146}));
  // Half-way between the last tissue voxel centre (z = 14 mm) and the next (15 mm): 0.5 level.
  EXPECT_NEAR(domain.value(kCentre_m + Point3{0.0, 0.0, 0.0145}), 0.0, 1e-12);
}

TEST(LabelVolumeDomain, ProjectsOntoTheHalfLevelNearTheSphere) {
  constexpr double kSpacing_m = 0.0005;
  const LabelVolumeDomain domain(testing::voxel_ball(kCentre_m, kRadius_m, kSpacing_m));
  for (int i = 0; i < 100; ++i) {
    const double t = 0.618033988749895 * i;
    Point3 direction{std::sin(7.0 * t), std::cos(5.0 * t), std::sin(3.0 * t + 1.0)};
    direction = (1.0 / norm(direction)) * direction;
    // From 3 mm inside to 6 mm outside: beyond the voxels' reach, where the indicator is flat.
    const Point3 p = kCentre_m + (kRadius_m + 0.006 * std::sin(11.0 * t) - 0.003) * direction;
    const Point3 q = domain.project_to_boundary(p);
    EXPECT_NEAR(domain.value(q), 0.0, 1e-6) << i;
    EXPECT_NEAR(norm(q - kCentre_m), kRadius_m, kSpacing_m) << i;
  }
}

}  // namespace
}  // namespace nav
