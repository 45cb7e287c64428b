// The blocked cubature kernels (nav/reduced/reduced_kernels.hpp) against a plain per-sample
// formulation written here from the full-order model's element data: the corotational and
// St Venant-Kirchhoff reduced forces and tangents agree to 1e-10 for several basis sizes and
// sample counts (padded blocks, tiles cut by r, a diaphragm lift); the evaluation never
// allocates and repeats bitwise; the interleaved polar decomposition matches nav's and does not
// depend on its neighbours; a display set reconstructs U q + L d.
#include <gtest/gtest.h>

#include <random>

#include "nav/reduced/reduced_forces.hpp"
#include "nav/reduced/reduced_kernels.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/st_venant_kirchhoff.hpp"
#include "nav/tissue/tet_fem_tables.hpp"
#include "nav/tissue/tet_kernels.hpp"
#include "reduced/reduced_test_support.hpp"
#include "support/allocation_guard.hpp"
#include "support/kernel_isas.hpp"

namespace nav {
namespace {

using testing::basis_matrix;
using testing::BeamScene;
using testing::nodes_where;

/// A beam held at x = 0 and prescribed at x = 3 cm, r modes, m sampled tetrahedra with
/// seeded weights, and a state (q, d) that rotates and stretches its elements.
struct KernelCase {
  BeamScene beam{{0.03, 0.01, 0.01}, 0.005};
  TissueSolverOptions solver;
  ReducedBasis basis;
  Eigen::VectorXd q;
  Eigen::Vector3d d{0.0004, -0.0006, 0.0009};

  KernelCase(ReducedForceKind kind, int r, int m) {
    solver.integrator = Integrator::quasi_static;
    if (kind == ReducedForceKind::stvk_cubature) {
      solver.law = ElementLaw::st_venant_kirchhoff;
      solver.incompressibility_gain_pa = 2.0e4;
    }
    beam.scene.prescribed_nodes = nodes_where(beam.mesh, 0, 0.03);
    ReductionOptions options;
    options.source = ReducedBasisSource::linear_modes;
    options.force_kind = kind;
    options.basis_size = r;
    basis = make_modal_basis(beam.mesh, beam.scene, solver, options).value();
    std::mt19937 random(static_cast<unsigned>(17 * r + m));
    std::uniform_real_distribution<double> weight(0.2, 3.0), coordinate(-1.0, 1.0);
    const std::size_t tets = beam.mesh.tets.size();
    for (int s = 0; s < m; ++s) {
      basis.sample_tets.push_back(
          static_cast<std::int32_t>(static_cast<std::size_t>(s) * tets / static_cast<std::size_t>(m)));
      basis.sample_weights.push_back(weight(random));
    }
    q = Eigen::VectorXd(r);
    for (int j = 0; j < r; ++j) q[j] = 0.012 * coordinate(random) / (1.0 + 0.3 * j);
  }
};

/// The reference: -K_r q - K_rl d plus, per sample, U_s^T w (f_s + K_s u_s) with f_s the
/// element's own force, and the tangent K_r - sum w U_s^T K_s U_s + the samples' tangents.
struct Reference {
  Eigen::VectorXd force;
  Eigen::MatrixXd tangent;
  int inverted = 0;
};

Reference reference(const KernelCase& c, const ReducedModel& model) {
  const TetFemModel full = make_tet_fem_model(c.beam.mesh, c.beam.scene, c.solver).value();
  const detail::TetFemTables& ft = full.tables();
  const detail::ReducedTables& t = model.tables();
  const int r = c.basis.basis_size;
  const Eigen::MatrixXd u = basis_matrix(c.basis);
  const auto n3 = u.rows();
  const Eigen::Map<const Eigen::MatrixXd> lift(c.basis.diaphragm_lift.data(), n3, 3);
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> kr(
      t.stiffness_r.data(), r, r);
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> krl(t.stiffness_lift_r.data(), r,
                                                                                        3);
  Reference out{-(kr * c.q + krl * c.d), kr, 0};
  const bool stvk = c.basis.force_kind == ReducedForceKind::stvk_cubature;
  for (std::size_t s = 0; s < c.basis.sample_tets.size(); ++s) {
    const auto e = static_cast<std::size_t>(c.basis.sample_tets[s]);
    const double w = c.basis.sample_weights[s];
    Eigen::MatrixXd ue(12, r);
    Eigen::Matrix<double, 12, 3> le;
    Eigen::Matrix<double, 12, 1> rest;
    Matrix43 gradients;
    for (int a = 0; a < 4; ++a) {
      const auto node = static_cast<Eigen::Index>(ft.tets[e][a]);
      ue.middleRows(3 * a, 3) = u.middleRows(3 * node, 3);
      le.middleRows(3 * a, 3) = lift.middleRows(3 * node, 3);
      for (int k = 0; k < 3; ++k) {
        rest[3 * a + k] = ft.rest_m[static_cast<std::size_t>(3 * node + k)];
        gradients(a, k) = ft.gradients[12 * e + static_cast<std::size_t>(3 * a + k)];
      }
    }
    const Eigen::Matrix<double, 12, 1> ve = ue * c.q + le * c.d;
    Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
    for (int a = 0; a < 4; ++a) f += ve.segment<3>(3 * a) * gradients.row(a);
    const Matrix12 ke = w * element_stiffness(gradients, ft.lame[e], ft.volume_m3[e]);
    Eigen::Matrix<double, 12, 1> fe;
    Matrix12 te;  // the sample's tangent (12 x 12)
    if (!(f.determinant() > 0.0)) ++out.inverted;
    if (stvk) {
      const Eigen::Matrix3d stress = stvk_stress(f, ft.lame[e], c.solver.incompressibility_gain_pa);
      const Eigen::Matrix3d tangent_stress = stvk_tangent_stress(f, ft.lame[e]);
      for (int a = 0; a < 4; ++a) fe.segment<3>(3 * a) = -w * ft.volume_m3[e] * (stress * gradients.row(a).transpose());
      for (int col = 0; col < 12; ++col) {  // column col of dF/du is e_(col%3) g_(col/3)^T
        Eigen::Matrix3d df = Eigen::Matrix3d::Zero();
        df.row(col % 3) = gradients.row(col / 3);
        const Eigen::Matrix3d dp =
            stvk_stress_derivative(f, df, tangent_stress, ft.lame[e], c.solver.incompressibility_gain_pa);
        for (int a = 0; a < 4; ++a)
          te.block<3, 1>(3 * a, col) = w * ft.volume_m3[e] * (dp * gradients.row(a).transpose());
      }
    } else {
      const Eigen::Matrix3d rotation = f.determinant() > 0.0 ? polar_rotation(f) : Eigen::Matrix3d::Identity();
      Matrix12 big = Matrix12::Zero();
      for (int a = 0; a < 4; ++a) big.block<3, 3>(3 * a, 3 * a) = rotation;
      fe = -big * ke * (big.transpose() * (rest + ve) - rest);
      te = big * ke * big.transpose();
    }
    out.force += ue.transpose() * (fe + ke * ve);
    out.tangent += ue.transpose() * (te - ke) * ue;
  }
  return out;
}

/// The kernels' force and tangent at the case's state, on fresh data.
struct Evaluated {
  std::vector<double> force, tangent;
  int inverted = 0;
  std::size_t allocations = 0;
};

Evaluated evaluate(const KernelCase& c, const ReducedModel& model) {
  auto data = make_reduced_data(model).value();
  const auto r = static_cast<std::size_t>(c.basis.basis_size);
  Evaluated out{std::vector<double>(r), std::vector<double>(r * r), 0, 0};
  const detail::ReducedState state{std::span<const double>(c.q.data(), r), c.d.data()};
  const detail::ForceScratch scratch{data.sample_displacements, data.sample_rotations, data.sample_tangent_rows,
                                     data.monomials};
  testing::AllocationGuard guard;
  out.inverted = detail::evaluate_internal_force(model.tables(), state, scratch, out.force, out.tangent);
  out.allocations = guard.allocations();
  return out;
}

void expect_kernels_equal_reference(ReducedForceKind kind) {
  for (int r : {3, 8, 13})
    for (int m : {1, 7, 8, 19, 40}) {
      const KernelCase c(kind, r, m);
      const auto model = make_reduced_model(c.beam.mesh, c.beam.scene, c.solver, c.basis, {});
      ASSERT_TRUE(model.ok()) << model.error().describe();
      const Reference expected = reference(c, model.value());
      const Evaluated got = evaluate(c, model.value());
      const Eigen::Map<const Eigen::VectorXd> force(got.force.data(), r);
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> tangent(
          got.tangent.data(), r, r);
      EXPECT_LT((force - expected.force).norm(), 1e-10 * expected.force.norm()) << "r " << r << " m " << m;
      EXPECT_LT((tangent - expected.tangent).cwiseAbs().maxCoeff(), 1e-10 * expected.tangent.cwiseAbs().maxCoeff())
          << "r " << r << " m " << m;
      EXPECT_EQ(got.inverted, expected.inverted);
      EXPECT_EQ(got.allocations, 0u);
      // The non-linear part matters: the force is not the linear one (the first sample alone
      // lies at the held end, where the basis vanishes).
      const detail::ReducedTables& t = model.value().tables();
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> kr(
          t.stiffness_r.data(), r, r);
      if (m > 1) {
        EXPECT_GT((force + kr * c.q).norm(), 1e-3 * force.norm()) << "r " << r << " m " << m;
      }
      const Evaluated again = evaluate(c, model.value());
      EXPECT_EQ(again.force, got.force);
      EXPECT_EQ(again.tangent, got.tangent);
    }
}

TEST(ReducedKernels, CorotationalForceAndTangentEqualThePlainFormulation) {
  expect_kernels_equal_reference(ReducedForceKind::corotational_cubature);
}

TEST(ReducedKernels, StvkForceAndTangentEqualThePlainFormulation) {
  expect_kernels_equal_reference(ReducedForceKind::stvk_cubature);
}

TEST(ReducedKernels, InterleavedPolarMatchesNavsAndIgnoresItsNeighbours) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> entry(-1.0, 1.0), stretch(0.05, 20.0);
  constexpr std::size_t kCount = 37;
  std::vector<Eigen::Matrix3d> matrices;
  while (matrices.size() < kCount) {  // rotations times stretches of 0.05 to 20 (conditions up to 400)
    Eigen::Matrix3d a;
    for (int k = 0; k < 9; ++k) a(k % 3, k / 3) = entry(random);
    const Eigen::Matrix3d rotation = Eigen::HouseholderQR<Eigen::Matrix3d>(a).householderQ();
    if (!(rotation.determinant() > 0.0)) continue;  // a reflection
    Eigen::Matrix3d s;
    for (int k = 0; k < 9; ++k) s(k % 3, k / 3) = 0.3 * entry(random);
    s = (s + s.transpose()).eval();
    s.diagonal() += Eigen::Vector3d(stretch(random), stretch(random), stretch(random));
    if (s.determinant() > 0.0 && Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(s).eigenvalues().minCoeff() > 0.0)
      matrices.push_back(rotation * s);
  }
  std::vector<double> all(9 * kCount);
  for (std::size_t n = 0; n < kCount; ++n)
    for (std::size_t k = 0; k < 9; ++k)
      all[k * kCount + n] = matrices[n](static_cast<Eigen::Index>(k % 3), static_cast<Eigen::Index>(k / 3));
  const std::vector<double> start = all;
  detail::reduced_lane_kernels(KernelIsa::baseline).polar_rotations(all.data(), kCount);
  for (std::size_t n = 0; n < kCount; ++n) {
    Eigen::Matrix3d got;
    double alone[9];
    for (std::size_t k = 0; k < 9; ++k)
      alone[k] = matrices[n](static_cast<Eigen::Index>(k % 3), static_cast<Eigen::Index>(k / 3));
    detail::reduced_lane_kernels(KernelIsa::baseline).polar_rotations(alone, 1);
    for (std::size_t k = 0; k < 9; ++k) {
      got(static_cast<Eigen::Index>(k % 3), static_cast<Eigen::Index>(k / 3)) = all[k * kCount + n];
      EXPECT_EQ(alone[k], all[k * kCount + n]) << n;  // bitwise: a lane does not see the others
    }
    EXPECT_LT((got - polar_rotation(matrices[n])).cwiseAbs().maxCoeff(), 1e-12) << n;
    EXPECT_LT((got.transpose() * got - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-13) << n;
  }
  for (KernelIsa isa : testing::available_kernel_isas()) {  // every variant: the same bits
    std::vector<double> again = start;
    detail::reduced_lane_kernels(isa).polar_rotations(again.data(), kCount);
    EXPECT_EQ(again, all) << kernel_isa_name(isa);
  }
}

TEST(ReducedKernels, DisplaySetReconstructsTheSelectedNodes) {
  const KernelCase c(ReducedForceKind::corotational_cubature, 13, 19);
  const ReducedModel model = make_reduced_model(c.beam.mesh, c.beam.scene, c.solver, c.basis, {}).value();
  auto data = make_reduced_data(model).value();
  for (int j = 0; j < 13; ++j) data.q[static_cast<std::size_t>(j)] = c.q[j];
  for (int k = 0; k < 3; ++k) data.prescribed_m[k] = c.d[k];
  const std::int32_t last = static_cast<std::int32_t>(c.beam.mesh.nodes_m.size() - 1);
  const std::vector<std::int32_t> nodes{last, 0,  7, c.beam.scene.prescribed_nodes[0],
                                        3,    11, 5};  // 21 values: a partial panel
  const ReducedDisplaySet display = make_reduced_display_set(model, nodes).value();
  std::vector<double> expected(3 * nodes.size()), got(3 * nodes.size());
  reconstruct_displacements_m(model, data, nodes, expected);
  testing::AllocationGuard guard;
  reconstruct_display_m(model, data, display, got);
  EXPECT_EQ(guard.allocations(), 0u);
  double largest = 0.0;
  for (double value : expected) largest = std::max(largest, std::abs(value));
  ASSERT_GT(largest, 0.0);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], expected[i], 1e-13 * largest) << i;
  EXPECT_DOUBLE_EQ(got[9 + 2], c.d[2]);  // the prescribed node follows d
  const std::vector<std::int32_t> bad{0, last + 1};
  const auto refused = make_reduced_display_set(model, bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "nodes");
}

}  // namespace
}  // namespace nav
