// Verification of the St Venant-Kirchhoff element law (Picinbono's non-linear tensor-mass) and
// its incompressibility penalty: the gradient form equals the printed tensor-mass force once
// its two typos are corrected, rigid motions carry no force, forces are energy gradients, the
// law tends to linear elasticity at small strain, and the implicit tangent stays positive
// semi-definite under compression while exact under tension.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "nav/tissue/tet_fem_kernels.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_kernels.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::max_abs;

TissueSolverOptions stvk_options(double gain_pa) {
  TissueSolverOptions options;
  options.law = ElementLaw::st_venant_kirchhoff;
  options.incompressibility_gain_pa = gain_pa;
  options.integrator = Integrator::explicit_central_difference;
  return options;
}

/// Elastic restoring forces of `model` at positions x.
std::vector<double> forces_at(const TetFemModel& model, std::span<const double> x) {
  auto data = make_tet_fem_data(model).value();
  detail::update_element_rotations(model.tables(), x, data.element_rotations);
  std::vector<double> forces(x.size(), 0.0);
  detail::add_elastic_forces(model.tables(), x, data.element_rotations, forces);
  return forces;
}

/// Positions x = R X + t of the mesh for a rotation of `angle_rad` about (1, 2, 3).
std::vector<double> rigidly_moved(const TetMesh& mesh, double angle_rad) {
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(angle_rad, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  std::vector<double> x;
  for (const Point3& p : mesh.nodes_m) {
    const Eigen::Vector3d moved = r * Eigen::Vector3d(p[0], p[1], p[2]) + Eigen::Vector3d(0.01, -0.02, 0.005);
    x.insert(x.end(), {moved[0], moved[1], moved[2]});
  }
  return x;
}

/// Picinbono's eq. (15) force of one tetrahedron, computed literally from the stored tensors
/// B (eq. 8), vectors C and scalars D (eq. 14) with shape vectors `alpha` (rows) and displacements
/// u (columns), times the volume: the gradient of the element energy.
Eigen::Matrix<double, 3, 4> tensor_mass_force(const Matrix43& alpha, const Eigen::Matrix<double, 3, 4>& u,
                                              const LameParameters& lame, double volume_m3) {
  const double l = lame.lambda_pa, m = lame.mu_pa;
  const auto a = [&](int j) { return Eigen::Vector3d(alpha.row(j).transpose()); };
  const auto b = [&](int j, int k) {
    return Eigen::Matrix3d(0.5 * l * a(j) * a(k).transpose() +
                           0.5 * m * (a(k) * a(j).transpose() + a(j).dot(a(k)) * Eigen::Matrix3d::Identity()));
  };
  const auto c = [&](int j, int k, int q) {
    return Eigen::Vector3d(0.5 * l * a(j) * a(k).dot(a(q)) + 0.5 * m * (a(q) * a(j).dot(a(k)) + a(k) * a(j).dot(a(q))));
  };
  const auto d = [&](int j, int k, int q, int s) {
    return 0.125 * l * a(j).dot(a(k)) * a(q).dot(a(s)) + 0.25 * m * a(j).dot(a(s)) * a(k).dot(a(q));
  };
  Eigen::Matrix<double, 3, 4> force = Eigen::Matrix<double, 3, 4>::Zero();
  for (int p = 0; p < 4; ++p) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) {
      f += 2.0 * b(p, j) * u.col(j);
      for (int k = 0; k < 4; ++k) {
        f += 2.0 * u.col(k) * u.col(j).dot(c(j, k, p)) + u.col(j).dot(u.col(k)) * c(p, j, k);
        for (int q = 0; q < 4; ++q) f += 4.0 * d(j, k, q, p) * u.col(k).dot(u.col(j)) * u.col(q);
      }
    }
    force.col(p) = volume_m3 * f;
  }
  return force;
}

}  // namespace

// The gradient form equals Picinbono's eq. (15) with alpha_j = +grad Lambda_j and the volume
// factor folded in (to 1e-10 of the force), on a random tetrahedron under a large random
// displacement. With the printed sign of eq. (6) (alpha = -grad Lambda) the cubic terms flip
// and a rigid rotation of 90 degrees produces a force of the order of the linear one.
TEST(StvkVerification, GradientFormEqualsCorrectedTensorMassForce) {
  TetMesh mesh;
  mesh.nodes_m = {{0.0, 0.0, 0.0}, {0.011, 0.001, -0.002}, {0.002, 0.009, 0.001}, {-0.001, 0.002, 0.012}};
  mesh.tets = {{0, 1, 2, 3}};
  TissueScene scene;
  scene.default_material = {8.0e3, 0.4, 1000.0};
  const auto model = make_tet_fem_model(mesh, scene, stvk_options(0.0));
  ASSERT_TRUE(model.ok()) << model.error().describe();
  const LameParameters lame = lame_parameters(scene.default_material);
  const Matrix43 alpha = shape_gradients({mesh.nodes_m[0], mesh.nodes_m[1], mesh.nodes_m[2], mesh.nodes_m[3]});
  const double volume_m3 = model.value().tables().volume_m3[0];

  Eigen::Matrix<double, 3, 4> u;
  u << 0.002, -0.003, 0.001, 0.004, 0.001, 0.002, -0.004, 0.000, -0.002, 0.003, 0.001, -0.003;
  std::vector<double> x;
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) x.push_back(mesh.nodes_m[a][i] + u(i, a));
  const std::vector<double> ours = forces_at(model.value(), x);
  const Eigen::Matrix<double, 3, 4> printed = tensor_mass_force(alpha, u, lame, volume_m3);
  const double scale_n = printed.cwiseAbs().maxCoeff();
  ASSERT_GT(scale_n, 0.0);
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(ours[3 * a + i], -printed(i, a), 1e-10 * scale_n);

  const Eigen::Matrix3d r = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d(0.0, 0.6, 0.8)).toRotationMatrix();
  Eigen::Matrix<double, 3, 4> rotation_u;
  for (int a = 0; a < 4; ++a) {
    const Eigen::Vector3d p(mesh.nodes_m[a][0], mesh.nodes_m[a][1], mesh.nodes_m[a][2]);
    rotation_u.col(a) = r * p - p;
  }
  const double correct_n = tensor_mass_force(alpha, rotation_u, lame, volume_m3).cwiseAbs().maxCoeff();
  const double printed_sign_n = tensor_mass_force(-alpha, rotation_u, lame, volume_m3).cwiseAbs().maxCoeff();
  const double linear_n = (volume_m3 * 2.0 * lame.mu_pa * 0.01);  // force scale of a unit rotation strain
  EXPECT_LT(correct_n, 1e-9 * linear_n);
  EXPECT_GT(printed_sign_n, 1e-2 * linear_n);
}

// A rigid motion (rotation of 30, 90 and 180 degrees plus a translation) carries no elastic
// force under St Venant-Kirchhoff, with or without the penalty (1e-9 of E h^2); the linear
// law's spurious force grows with the angle (measured and printed).
TEST(StvkVerification, RigidMotionCarriesNoForce) {
  const TetMesh mesh = box_mesh({0.02, 0.02, 0.04}, 0.005);
  TissueScene scene;
  scene.default_material = {5.0e3, 0.45, 1000.0};
  const double scale_n = 5.0e3 * 0.005 * 0.005;
  TissueSolverOptions linear = stvk_options(0.0);
  linear.law = ElementLaw::linear_elastic;
  linear.rotation = ElementRotation::none;
  const auto linear_model = make_tet_fem_model(mesh, scene, linear);
  ASSERT_TRUE(linear_model.ok());
  double previous_linear_n = 0.0;
  for (double angle_deg : {30.0, 90.0, 180.0}) {
    const std::vector<double> x = rigidly_moved(mesh, angle_deg * M_PI / 180.0);
    for (double gain_pa : {0.0, 5.0e4}) {
      const auto model = make_tet_fem_model(mesh, scene, stvk_options(gain_pa));
      ASSERT_TRUE(model.ok());
      EXPECT_LT(max_abs(forces_at(model.value(), x)), 1e-9 * scale_n) << angle_deg << " degrees, gain " << gain_pa;
    }
    const double linear_n = max_abs(forces_at(linear_model.value(), x));
    std::printf("linear law, rigid rotation of %.0f degrees: spurious nodal force %.3g N (%.3g E h^2)\n", angle_deg,
                linear_n, linear_n / scale_n);
    EXPECT_GT(linear_n, previous_linear_n);
    previous_linear_n = linear_n;
  }
  EXPECT_GT(previous_linear_n, 0.1 * scale_n);
}

// Forces are minus the gradient of elastic_energy_j: central differences of step 1e-8 m agree
// to 1e-5 of the largest force, with the penalty switched on, under a 20 % deformation.
TEST(StvkVerification, ForcesAreEnergyGradients) {
  const TetMesh mesh = box_mesh({0.01, 0.01, 0.01}, 0.005);
  TissueScene scene;
  scene.default_material = {5.0e3, 0.3, 1000.0};
  const auto model = make_tet_fem_model(mesh, scene, stvk_options(2.0e5));
  ASSERT_TRUE(model.ok());
  auto data = make_tet_fem_data(model.value()).value();
  for (std::size_t i = 0; i < data.positions_m.size(); ++i)
    data.positions_m[i] += 0.002 * std::sin(1.7 * static_cast<double>(i)) - (i % 3 == 2 ? 0.0015 : 0.0);
  const std::vector<double> x(data.positions_m.begin(), data.positions_m.end());
  const std::vector<double> forces = forces_at(model.value(), x);
  const double scale_n = max_abs(forces);
  const double step_m = 1e-8;
  for (std::size_t i = 0; i < x.size(); i += 5) {
    data.positions_m[i] = x[i] + step_m;
    const double up_j = elastic_energy_j(model.value(), data);
    data.positions_m[i] = x[i] - step_m;
    const double down_j = elastic_energy_j(model.value(), data);
    data.positions_m[i] = x[i];
    EXPECT_NEAR(forces[i], -(up_j - down_j) / (2.0 * step_m), 1e-5 * scale_n) << "dof " << i;
  }
}

// At small strain St Venant-Kirchhoff tends to linear elasticity: under u = eps G X (|G| about
// 1.5) the relative difference of the nodal forces is O(eps): below 5 eps, and halving eps
// halves it (ratio 2 +- 0.1).
TEST(StvkVerification, SmallStrainLimitIsLinear) {
  const TetMesh mesh = box_mesh({0.02, 0.02, 0.02}, 0.005);
  TissueScene scene;
  scene.default_material = {5.0e3, 0.4, 1000.0};
  TissueSolverOptions linear = stvk_options(0.0);
  linear.law = ElementLaw::linear_elastic;
  linear.rotation = ElementRotation::none;
  const auto stvk_model = make_tet_fem_model(mesh, scene, stvk_options(1.0e4));
  const auto linear_model = make_tet_fem_model(mesh, scene, linear);
  ASSERT_TRUE(stvk_model.ok() && linear_model.ok());
  const double g[3][3] = {{1.0, 0.4, -0.2}, {0.3, -0.6, 0.5}, {-0.2, 0.1, 0.8}};
  const auto relative_difference = [&](double eps) {
    std::vector<double> x;
    for (const Point3& p : mesh.nodes_m)
      for (int i = 0; i < 3; ++i) x.push_back(p[i] + eps * (g[i][0] * p[0] + g[i][1] * p[1] + g[i][2] * p[2]));
    const std::vector<double> a = forces_at(stvk_model.value(), x), b = forces_at(linear_model.value(), x);
    double difference = 0.0, size = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      difference += (a[i] - b[i]) * (a[i] - b[i]);
      size += b[i] * b[i];
    }
    return std::sqrt(difference / size);
  };
  for (double eps : {1e-2, 1e-3}) {
    const double at_eps = relative_difference(eps);
    EXPECT_LT(at_eps, 5.0 * eps);
    EXPECT_NEAR(at_eps / relative_difference(0.5 * eps), 2.0, 0.1) << eps;
  }
}

/// p^T K p and K p at positions x, with the tangent of the implicit solvers.
std::pair<double, std::vector<double>> tangent_product(const TetFemModel& model, std::span<const double> x,
                                                       std::span<const double> p) {
  auto data = make_tet_fem_data(model).value();
  detail::update_tangent_stresses(model.tables(), x, data.tangent_stresses);
  std::vector<double> product(x.size(), 0.0);
  detail::add_stiffness_product(model.tables(), x, data.element_rotations, data.tangent_stresses, p, 1.0, product);
  double curvature = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) curvature += p[i] * product[i];
  return {curvature, product};
}

/// -(f(x + h p) - f(x - h p)) / 2h: the exact tangent times p, by central differences.
std::vector<double> exact_tangent_product(const TetFemModel& model, std::span<const double> x,
                                          std::span<const double> p, double step_m) {
  std::vector<double> up(x.begin(), x.end()), down(x.begin(), x.end());
  for (std::size_t i = 0; i < x.size(); ++i) {
    up[i] += step_m * p[i];
    down[i] -= step_m * p[i];
  }
  const std::vector<double> f_up = forces_at(model, up), f_down = forces_at(model, down);
  std::vector<double> product(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) product[i] = -(f_up[i] - f_down[i]) / (2.0 * step_m);
  return product;
}

// Uniform compression to 70 % makes the second Piola-Kirchhoff stress negative definite, and
// the exact tangent indefinite: along an infinitesimal rotation p = W x its curvature p^T K p
// is negative (central differences). The implicit tangent, with the stress's positive part,
// keeps p^T K p >= 0 for that p and for 20 pseudo-random ones, with and without the penalty.
// Under a stretch with shear (tension) it equals the exact tangent to 1e-6.
TEST(StvkVerification, ImplicitTangentIsPositiveUnderCompressionAndExactUnderTension) {
  const TetMesh mesh = box_mesh({0.01, 0.01, 0.01}, 0.005);
  TissueScene scene;
  scene.default_material = {5.0e3, 0.4, 1000.0};
  std::vector<double> compressed, rotation;
  for (const Point3& q : mesh.nodes_m) {
    compressed.insert(compressed.end(), {0.7 * q[0], 0.7 * q[1], 0.7 * q[2]});
    rotation.insert(rotation.end(), {-0.7 * q[1], 0.7 * q[0], 0.0});
  }
  TissueSolverOptions implicit = stvk_options(0.0);
  implicit.integrator = Integrator::implicit_euler;
  const auto model = make_tet_fem_model(mesh, scene, implicit);
  ASSERT_TRUE(model.ok());
  double exact_curvature = 0.0;
  const std::vector<double> exact = exact_tangent_product(model.value(), compressed, rotation, 1e-7);
  for (std::size_t i = 0; i < exact.size(); ++i) exact_curvature += rotation[i] * exact[i];
  const double stiffness_scale = 5.0e3 * 0.01 * 0.01 * 0.01 * 0.01 / 0.005;  // E V |p|^2 / h^2, order of magnitude
  std::printf("curvature along a rotation at 70 %% compression: exact %.3g, implicit tangent %.3g (scale %.3g)\n",
              exact_curvature, tangent_product(model.value(), compressed, rotation).first, stiffness_scale);
  EXPECT_LT(exact_curvature, -1e-3 * stiffness_scale);
  for (double gain_pa : {0.0, 1.0e5}) {
    implicit.incompressibility_gain_pa = gain_pa;
    const auto penalised = make_tet_fem_model(mesh, scene, implicit);
    ASSERT_TRUE(penalised.ok());
    EXPECT_GE(tangent_product(penalised.value(), compressed, rotation).first, 0.0);
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<double> p(compressed.size());
      for (std::size_t i = 0; i < p.size(); ++i) p[i] = std::sin(0.37 * static_cast<double>(i * (trial + 3)) + trial);
      EXPECT_GE(tangent_product(penalised.value(), compressed, p).first, -1e-12 * stiffness_scale) << trial;
    }
  }
  std::vector<double> stretched, p;
  for (const Point3& q : mesh.nodes_m) {
    stretched.insert(stretched.end(), {1.2 * q[0] + 0.1 * q[1], 1.1 * q[1], 1.15 * q[2]});
    p.insert(p.end(), {std::sin(40.0 * q[1]), std::cos(60.0 * q[2]), std::sin(50.0 * q[0] + 1.0)});
  }
  implicit.incompressibility_gain_pa = 0.0;
  const auto tension_model = make_tet_fem_model(mesh, scene, implicit);
  const std::vector<double> ours = tangent_product(tension_model.value(), stretched, p).second;
  const std::vector<double> reference = exact_tangent_product(tension_model.value(), stretched, p, 1e-7);
  const double size = max_abs(reference);
  for (std::size_t i = 0; i < ours.size(); ++i) EXPECT_NEAR(ours[i], reference[i], 1e-6 * size) << "dof " << i;
}

}  // namespace nav
