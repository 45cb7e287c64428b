// Point registration (Horn/Umeyama) and surface ICP against synthetic truth: exact without
// noise; with fiducial noise, FRE and TRE agree with Fitzpatrick's predictions; the liver
// surface registered from noisy surface points; collinear and coplanar input refused.
#include <gtest/gtest.h>

#include <cstdio>

#include "calibration_truth.hpp"
#include "nav/calibration/point_registration.hpp"
#include "nav/calibration/surface_icp.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

using namespace nav::calibration::testing;

const std::vector<Eigen::Vector3d> kFiducials_m{{0.00, 0.00, 0.00}, {0.10, 0.01, 0.00},  {0.02, 0.12, 0.01},
                                                {0.09, 0.10, 0.05}, {-0.03, 0.05, 0.08}, {0.05, -0.04, 0.06}};

TEST(PointRegistration, ExactWithoutNoise) {
  std::mt19937_64 rng(31);
  const Transform truth = transform(random_rotation(rng, 3.0), {0.3, -0.1, 0.7});
  std::vector<Eigen::Vector3d> moved;
  for (const auto& p : kFiducials_m) moved.push_back(truth * p);
  auto result = register_points(kFiducials_m, moved);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  EXPECT_TRUE(result.value().target_from_source.isApprox(truth, 1e-12));
  EXPECT_LT(result.value().fre_rms_m, 1e-12);
}

// Fitzpatrick, West and Maurer (1998): <FRE^2> = (1 - 2/N) FLE^2 and
// <TRE^2(r)> = FLE^2 / N (1 + 1/3 sum_k d_k^2 / f_k^2), with FLE^2 the mean squared 3-D
// localisation error, d_k the target's and f_k the fiducials' RMS distance to principal axis k.
double predicted_tre2(const std::vector<Eigen::Vector3d>& fiducials, const Eigen::Vector3d& target, double fle2) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : fiducials) mean += p / static_cast<double>(fiducials.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : fiducials) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(scatter, Eigen::ComputeFullU);
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d axis = svd.matrixU().col(k);
    auto distance2 = [&](const Eigen::Vector3d& p) {
      return (p - mean).squaredNorm() - std::pow((p - mean).dot(axis), 2);
    };
    double f2 = 0.0;
    for (const auto& p : fiducials) f2 += distance2(p) / static_cast<double>(fiducials.size());
    sum += distance2(target) / f2;
  }
  return fle2 / static_cast<double>(fiducials.size()) * (1.0 + sum / 3.0);
}

TEST(PointRegistration, FreAndTreMatchFitzpatrickAcrossNoiseLevels) {
  std::mt19937_64 rng(32);
  const Eigen::Vector3d target_m(0.05, 0.05, 0.15);  // a target beyond the fiducials
  const int trials = 2000;
  for (const double sigma_m : {0.25e-3, 0.5e-3, 1.0e-3}) {
    double fre2 = 0.0, tre2 = 0.0;
    for (int trial = 0; trial < trials; ++trial) {
      const Transform truth = transform(random_rotation(rng, 3.0), gaussian_vector(rng, 0.2));
      std::vector<Eigen::Vector3d> measured;
      for (const auto& p : kFiducials_m) measured.push_back(truth * p + gaussian_vector(rng, sigma_m));
      auto result = register_points(kFiducials_m, measured);
      ASSERT_TRUE(result.ok());
      fre2 += std::pow(result.value().fre_rms_m, 2) / trials;
      tre2 +=
          std::pow(target_registration_error_m(result.value().target_from_source, {target_m}, {truth * target_m}), 2) /
          trials;
    }
    const double fle2 = 3.0 * sigma_m * sigma_m;
    const double n = static_cast<double>(kFiducials_m.size());
    std::printf("registration: FLE %.2f mm/axis: RMS FRE %.3f mm (predicted %.3f), RMS TRE %.3f mm (predicted %.3f)\n",
                sigma_m * 1e3, std::sqrt(fre2) * 1e3, std::sqrt((1.0 - 2.0 / n) * fle2) * 1e3, std::sqrt(tre2) * 1e3,
                std::sqrt(predicted_tre2(kFiducials_m, target_m, fle2)) * 1e3);
    EXPECT_NEAR(fre2 / ((1.0 - 2.0 / n) * fle2), 1.0, 0.1);
    EXPECT_NEAR(tre2 / predicted_tre2(kFiducials_m, target_m, fle2), 1.0, 0.15);
  }
}

TEST(PointRegistration, CollinearPointsAreRefused) {
  const std::vector<Eigen::Vector3d> line{{0, 0, 0}, {0.1, 0, 0}, {0.2, 0, 0}, {0.3, 0, 0}};
  auto result = register_points(line, line);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("collinear"), std::string::npos);
  EXPECT_FALSE(register_points({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}).ok());
}

TEST(SurfaceIcp, RegistersTheLiverSurfaceFromNoisyPoints) {
  const std::string path = nav::testing::shared_data_path("liver/liver-smoothUV.obj");
  NAV_REQUIRE_SHARED_DATA(path);
  auto surface = load_surface(path, LengthUnit::centimetre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  const TriSurface& liver = surface.value();
  std::mt19937_64 rng(33);
  // The truth points_from_surface: 6 degrees and 6 mm off; the points are sampled on the
  // surface, moved by it and given 0.3 mm of noise per axis.
  const Transform points_from_surface = transform(random_rotation(rng, 6.0 * M_PI / 180.0), {0.004, -0.003, 0.0035});
  std::uniform_int_distribution<std::size_t> pick(0, liver.triangles.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto vertex = [&](std::int32_t i) {
    const Point3& p = liver.vertices_m[static_cast<std::size_t>(i)];
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int i = 0; i < 300; ++i) {
    const auto& tri = liver.triangles[pick(rng)];
    double u = unit(rng), v = unit(rng);
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    const Eigen::Vector3d on_surface =
        vertex(tri[0]) + u * (vertex(tri[1]) - vertex(tri[0])) + v * (vertex(tri[2]) - vertex(tri[0]));
    centroid += on_surface / 300.0;
    points.push_back(points_from_surface * on_surface + gaussian_vector(rng, 0.3e-3));
  }
  auto result = surface_icp(liver, points, Transform::Identity());
  ASSERT_TRUE(result.ok()) << result.error().describe();
  // TRE at the liver's centre (a tumour-like deep target) and at a far surface vertex.
  const Transform recovered = result.value().surface_from_points;
  const Eigen::Vector3d far = vertex(0);
  const double tre_m = target_registration_error_m(
      recovered, {points_from_surface * centroid, points_from_surface * far}, {centroid, far});
  std::printf("surface ICP: %d iterations, RMS distance %.3f mm, TRE %.3f mm (0.3 mm/axis point noise)\n",
              result.value().iterations, result.value().rms_distance_m * 1e3, tre_m * 1e3);
  EXPECT_LT(tre_m, 1.0e-3);
  EXPECT_LT(result.value().rms_distance_m, 0.6e-3);
}

TEST(SurfaceIcp, CoplanarPointsAreRefused) {
  TriSurface square{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}};
  std::vector<Eigen::Vector3d> flat;
  for (int i = 0; i < 10; ++i) flat.emplace_back(0.01 * i, 0.02 * (i % 3), 0.0);
  auto result = surface_icp(square, flat, Transform::Identity());
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("coplanar"), std::string::npos);
}

TEST(SurfaceIcp, ClosestPointOnTriangleRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(closest_point_on_triangle({0.2, 0.3, 5.0}, a, b, c).isApprox(Eigen::Vector3d(0.2, 0.3, 0.0)));
  EXPECT_TRUE(closest_point_on_triangle({-1, -1, 0}, a, b, c).isApprox(a));
  EXPECT_TRUE(closest_point_on_triangle({0.5, -2, 1}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_TRUE(closest_point_on_triangle({1, 1, 0}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0.5, 0)));
}

}  // namespace
}  // namespace nav::calibration
