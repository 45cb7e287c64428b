// The needle coupled to the reduced-order tissue: the compliance factors equal the reduced
// step's own response to point forces; an insertion punctures and drags the tissue along
// the shaft as the coupling to the full-order tissue does (a complete linear basis against
// the exact linear full-order tissue); the multi-rate mode keeps the puncture; coupled
// ticks allocate nothing and repeat bitwise; the solver's W equals H A^-1 H^T + C C^T (+ the
// local compliance) by dense algebra, and with the full-order tissue H A^-1 H^T + the tissue's
// stepped responses at the rows' nodes; the compliance a truncated basis misses at a node,
// added back, makes the node's compliance the full order's and its puncture the full order's,
// and between nodes, the solver's W the full order's;
// bad couplings are refused by name.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <span>

#include "nav/needle/missing_node_compliance.hpp"
#include "nav/needle/reduced_coupling.hpp"
#include "nav/needle/tissue_coupling.hpp"
#include "nav/reduced/reduction.hpp"
#include "needle_coupling_support.hpp"
#include "needle_insertion_support.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

constexpr double kSideM = 0.04, kDepthM = 0.02;

/// A 4 x 4 x 2 cm slab of 20 kPa tissue in 1 cm elements, held at its bottom face.
struct Slab {
  TetMesh mesh = testing::box_mesh({kSideM, kSideM, kDepthM}, 0.01);
  TissueScene scene = testing::held_at_bottom(mesh);
  int free_dofs() const { return 3 * static_cast<int>(mesh.nodes_m.size() - scene.fixed_nodes.size()); }
};

/// The slab's first r vibration modes with the given force reduction (corotational: every
/// tetrahedron sampled with weight 1, the exact projection).
ReducedModel reduced_slab(const Slab& slab, int r, ReducedForceKind kind, ReducedIntegrator integrator) {
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.force_kind = kind;
  options.basis_size = r;
  const TissueSolverOptions solver =
      kind == ReducedForceKind::linear ? testing::exact_linear_options() : TissueSolverOptions{};
  ReducedBasis basis = make_modal_basis(slab.mesh, slab.scene, solver, options).value();
  if (kind != ReducedForceKind::linear)
    for (std::size_t t = 0; t < slab.mesh.tets.size(); ++t) {
      basis.sample_tets.push_back(static_cast<std::int32_t>(t));
      basis.sample_weights.push_back(1.0);
    }
  ReducedSolverOptions reduced;
  reduced.integrator = integrator;
  auto model = make_reduced_model(slab.mesh, slab.scene, solver, basis, reduced);
  EXPECT_TRUE(model.ok()) << model.error().describe();
  return std::move(model).value();
}

/// The needle pointing down (-z) above the top face's centre, 5 mm off it.
NeedlePose above_slab(double lowered_m) {
  return testing::needle_above(0.5 * kSideM, 0.5 * kSideM, kDepthM, lowered_m);
}

NeedleTissueScene slab_top_layer(double path_spacing_m = 0.003) {
  return testing::top_face_layer(0.5 * kSideM, 0.5 * kSideM, kDepthM, path_spacing_m);
}

/// The reduced tissue's compliance factors a coupled model carries.
ReducedComplianceFactors factors_of(const NeedleTissueModel& interaction) {
  return {interaction.compliance_rank, interaction.compliance_factors};
}

/// Lowers the needle by `travel_m` from where it is; returns the lowering at puncture (-1: none).
template <class Model, class Data>
double insert(const Model& model, Data& data, double from_m, double travel_m) {
  double at_puncture_m = -1.0;
  NeedleInputs inputs;
  for (int s = 1; s * testing::kInsertionStepM <= travel_m + 1e-12; ++s) {
    inputs.base = above_slab(from_m + s * testing::kInsertionStepM);
    step(model, data, inputs);
    if (at_puncture_m < 0.0 && data.interaction.report.punctures > 0)
      at_puncture_m = from_m + s * testing::kInsertionStepM;
  }
  return at_puncture_m;
}

/// The mean displacement along the insertion (-z) of the nodes that carry active path points.
double mean_drag_m(const NeedleTissueData& interaction, std::span<const double> displacements_m, int& points) {
  double sum = 0.0;
  points = 0;
  for (const PathPoint& p : interaction.path)
    if (p.active) {
      sum -= displacements_m[3 * static_cast<std::size_t>(p.tissue.node) + 2];
      ++points;
    }
  return points > 0 ? sum / points : 0.0;
}

TEST(NeedleReducedCoupling, ComplianceFactorsEqualTheReducedStepResponse) {
  const Slab slab;
  for (ReducedIntegrator integrator : {ReducedIntegrator::implicit_euler, ReducedIntegrator::quasi_static}) {
    const ReducedModel tissue = reduced_slab(slab, 16, ReducedForceKind::corotational_cubature, integrator);
    const auto factors = reduced_compliance_factors(tissue, 0.01);
    ASSERT_TRUE(factors.ok()) << factors.error().describe();
    const int r = factors.value().rank;
    ASSERT_EQ(r, 16);
    const auto rows = [&](std::size_t node) {
      return Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>>(
          factors.value().factors.data() + 3 * node * r, 3, r);
    };
    const std::size_t nodes = slab.mesh.nodes_m.size();
    std::vector<double> u(3 * nodes);
    double worst = 0.0;
    // Forces of 0.37 N along each axis on the top face's nodes, every node's response.
    for (const std::int32_t top : testing::nodes_where(slab.mesh, 2, kDepthM))
      for (int axis = 0; axis < 3; ++axis) {
        const auto loaded = static_cast<std::size_t>(top);
        auto data = make_reduced_data(tissue).value();
        PointForce force{static_cast<std::int32_t>(loaded), {0.0, 0.0, 0.0}};
        force.force_n[static_cast<std::size_t>(axis)] = 0.37;
        TissueInputs inputs;
        inputs.point_forces = std::span<const PointForce>(&force, 1);
        step(tissue, data, inputs);
        reconstruct_all_displacements_m(tissue, data, u);
        double largest = 0.0, error = 0.0;
        for (std::size_t node = 0; node < nodes; ++node) {
          const Eigen::Vector3d predicted = 0.37 * rows(node) * rows(loaded).row(axis).transpose();
          const Eigen::Vector3d measured = Eigen::Map<const Eigen::Vector3d>(u.data() + 3 * node);
          largest = std::max(largest, measured.cwiseAbs().maxCoeff());
          error = std::max(error, (predicted - measured).cwiseAbs().maxCoeff());
        }
        ASSERT_GT(largest, 0.0);
        worst = std::max(worst, error / largest);
      }
    std::printf("%s: largest relative difference of V V^T from the reduced step's response %.2e\n",
                integrator == ReducedIntegrator::quasi_static ? "quasi-static" : "implicit Euler", worst);
    EXPECT_LT(worst, 1e-10);
  }
}

TEST(NeedleReducedCoupling, InsertionPuncturesAndDragsTheTissueAsTheFullOrderCouplingDoes) {
  const Slab slab;
  // The same linear tissue twice: exact full order, and its complete reduced basis.
  const TetFemModel full = make_tet_fem_model(slab.mesh, slab.scene, testing::exact_linear_options()).value();
  const ReducedModel reduced =
      reduced_slab(slab, slab.free_dofs(), ReducedForceKind::linear, ReducedIntegrator::quasi_static);
  // Neither misses any local compliance: the full order's nodes and a complete basis.
  NeedleTissueScene complete = slab_top_layer(0.01);
  complete.point_compliance_m_per_n = 1e-8;
  const CoupledNeedleModel full_model = make_coupled_needle_model(NeedleParameters{}, complete, full, 32, 1).value();
  const ReducedCoupledNeedleModel reduced_model =
      make_coupled_needle_model(NeedleParameters{}, complete, reduced, slab.mesh, 32, 1).value();
  CoupledNeedleData full_data = make_coupled_needle_data(full_model, above_slab(0.0)).value();
  ReducedCoupledNeedleData reduced_data = make_coupled_needle_data(reduced_model, above_slab(0.0)).value();
  const double full_puncture_m = insert(full_model, full_data, 0.0, 0.02);
  const double reduced_puncture_m = insert(reduced_model, reduced_data, 0.0, 0.02);
  int full_points = 0, reduced_points = 0;
  const double full_drag_m = mean_drag_m(full_data.interaction, full_data.displacements_m, full_points);
  const double reduced_drag_m = mean_drag_m(reduced_data.interaction, reduced_data.displacements_m, reduced_points);
  std::printf(
      "puncture after lowering %.2f mm (full order) and %.2f mm (reduced); path points %d / %d; mean drag along "
      "the shaft %.3f / %.3f um\n",
      1e3 * full_puncture_m, 1e3 * reduced_puncture_m, full_points, reduced_points, 1e6 * full_drag_m,
      1e6 * reduced_drag_m);
  EXPECT_EQ(reduced_data.interaction.report.punctures, 1);
  EXPECT_GT(reduced_puncture_m, 0.005);  // after the 5 mm gap
  EXPECT_GT(reduced_points, 0);
  EXPECT_GT(reduced_drag_m, 0.0);
  EXPECT_LT(reduced_data.interaction.report.residual_m, reduced_model.interaction.scene.residual_bound_m);
  EXPECT_FALSE(reduced_data.interaction.health.has(HealthFlag::non_finite_state));
  // Same tissue, the same compliance inside a tick (the full order's responses at the nodes
  // in use, solved with its factor; the complete basis's V V^T), both stepping the tissue
  // every tick to its equilibrium: the puncture depth within 2 % (and one tick of lowering),
  // the drag within 2 %.
  EXPECT_NEAR(reduced_puncture_m / full_puncture_m, 1.0, 0.02);
  EXPECT_NEAR(reduced_puncture_m, full_puncture_m, testing::kInsertionStepM + 1e-9);
  EXPECT_EQ(reduced_points, full_points);
  EXPECT_NEAR(reduced_drag_m / full_drag_m, 1.0, 0.02);
}

TEST(NeedleReducedCoupling, SignoriniAndCoulombHoldOnTheSteppedReducedTissue) {
  // The tissue steps every tick: after it, each tissue point has moved by its node's new
  // reduced displacement (and yields locally under its own force), which must satisfy the
  // rows' laws with the corrected needle as the solver predicted through V V^T.
  const Slab slab;
  const ReducedModel tissue =
      reduced_slab(slab, 16, ReducedForceKind::corotational_cubature, ReducedIntegrator::quasi_static);
  const ReducedCoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), tissue, slab.mesh, 32, 1).value();
  ReducedCoupledNeedleData data = make_coupled_needle_data(model, above_slab(0.0)).value();
  std::vector<double> before(data.displacements_m.size());
  double worst_m = 0.0;
  int checked = 0;
  NeedleInputs inputs;
  int last_rows = 0;
  for (int s = 1; s * testing::kInsertionStepM <= 0.012; ++s) {
    std::copy(data.displacements_m.begin(), data.displacements_m.end(), before.begin());
    inputs.base = above_slab(s * testing::kInsertionStepM);
    step(model, data, inputs);
    // Skip the ticks whose rows changed: a freed slot's force (the capsule's f_p at the
    // puncture) leaves the tissue at its step, unannounced to the solver (by design).
    const bool same_rows = data.interaction.row_count == last_rows;
    last_rows = data.interaction.row_count;
    if (data.interaction.row_count == 0 || !same_rows) continue;
    const double local = model.interaction.scene.point_compliance_m_per_n;
    worst_m = std::max(worst_m, testing::violation_after_correction(data.interaction, [&](std::size_t r) {
                         const ConstraintRow& row = data.interaction.rows[r];
                         const auto node = 3 * static_cast<std::size_t>(row.tissue_node);
                         Eigen::Vector3d x = row.tissue_point_m;
                         for (int c = 0; c < 3; ++c) x[c] += data.displacements_m[node + c] - before[node + c];
                         for (int k = 0; k < data.interaction.row_count; ++k) {
                           const ConstraintRow& other = data.interaction.rows[static_cast<std::size_t>(k)];
                           if (same_constraint_point(row, other))
                             x -= local * data.interaction.row_forces[static_cast<std::size_t>(k)] * other.direction;
                         }
                         return x;
                       }));
    ++checked;
  }
  std::printf("%d ticks with constraints, largest law violation on the stepped tissue %.2e m\n", checked, worst_m);
  EXPECT_GT(checked, 100);
  EXPECT_EQ(data.interaction.report.punctures, 1);
  EXPECT_LT(worst_m, 1e-5);
}

/// W by dense algebra, apart from the solver's own: the needle's A^-1 from the assembled
/// block-tridiagonal A inverted whole, the tissue's V V^T from the factors per row, and the
/// local compliance on each constraint point's own rows.
/// The solver's W by dense algebra: H A^-1 H^T (the needle's block-tridiagonal system inverted
/// densely) plus the tissue's d_r^T C(node_r, node_s) d_s (`tissue_block(a, b)`: node a's
/// displacement per newton on node b) plus the local compliance on each point's own rows.
template <class TissueBlock>
Eigen::MatrixXd dense_compliance(const NeedleTissueModel& model, const NeedleTissueData& data,
                                 TissueBlock tissue_block) {
  const BlockTridiagonal& system = data.needle.system;
  const Eigen::Index n = 6 * system.blocks;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < system.blocks; ++k) {
    a.block<6, 6>(6 * k, 6 * k) = Eigen::Map<const Eigen::Matrix<double, 6, 6>>(system.diagonal.data() + 36 * k);
    if (k + 1 < system.blocks) {
      a.block<6, 6>(6 * k, 6 * k + 6) = Eigen::Map<const Eigen::Matrix<double, 6, 6>>(system.upper.data() + 36 * k);
      a.block<6, 6>(6 * k + 6, 6 * k) = a.block<6, 6>(6 * k, 6 * k + 6).transpose();
    }
  }
  const Eigen::MatrixXd inverse = a.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  const auto m = static_cast<Eigen::Index>(data.row_count);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m, n), tissue = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index r = 0; r < m; ++r) {
    const ConstraintRow& row = data.rows[static_cast<std::size_t>(r)];
    for (int k = 0; k < 2; ++k) {
      const int node = row.node + k;
      const double w = k == 0 ? 1.0 - row.weight : row.weight;
      if (node >= 1 && w != 0.0) h.block<1, 3>(r, 6 * (node - 1)) = w * row.direction.transpose();
    }
    for (Eigen::Index c = 0; c < m; ++c) {
      const ConstraintRow& other = data.rows[static_cast<std::size_t>(c)];
      if (row.tissue_node >= 0 && other.tissue_node >= 0)
        tissue(r, c) = row.direction.dot(tissue_block(row.tissue_node, other.tissue_node) * other.direction);
    }
  }
  Eigen::MatrixXd w = h * inverse * h.transpose() + tissue;
  for (int p = 0; p < data.point_count; ++p)
    for (int r = data.point_first_row[static_cast<std::size_t>(p)];
         r < data.point_first_row[static_cast<std::size_t>(p) + 1]; ++r)
      for (int s = data.point_first_row[static_cast<std::size_t>(p)];
           s < data.point_first_row[static_cast<std::size_t>(p) + 1]; ++s)
        w(r, s) += model.scene.point_compliance_m_per_n * data.rows[static_cast<std::size_t>(r)].direction.dot(
                                                              data.rows[static_cast<std::size_t>(s)].direction);
  return w;
}

/// The largest difference between the solver's W and `dense`, relative to dense's largest
/// entry, printed; and whether the solver's is exactly symmetric.
double compared_with_dense(const NeedleTissueData& interaction, const Eigen::MatrixXd& dense, bool& symmetric) {
  const auto m = static_cast<Eigen::Index>(interaction.row_count);
  const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> solver(
      interaction.compliance.data(), m, m,
      Eigen::OuterStride<>(static_cast<Eigen::Index>(interaction.compliance_stride)));
  const double error = (solver - dense).cwiseAbs().maxCoeff() / dense.cwiseAbs().maxCoeff();
  std::printf("%lld rows on %d constraint points: largest difference from the dense W %.2e of its largest entry\n",
              static_cast<long long>(m), interaction.point_count, error);
  symmetric = solver == solver.transpose();
  return error;
}

/// Node a's displacement per newton on node b over one step of `full` from rest, by its own
/// step (column j: a unit force along axis j).
Eigen::Matrix3d stepped_response_block(const TetFemModel& full, std::int32_t a, std::int32_t b) {
  const std::span<const double> rest = full.rest_positions_m();
  Eigen::Matrix3d block;
  for (int j = 0; j < 3; ++j) {
    TetFemData tissue = make_tet_fem_data(full).value();
    PointForce unit{b, {}};
    unit.force_n[static_cast<std::size_t>(j)] = 1.0;
    TissueInputs inputs;
    inputs.point_forces = std::span<const PointForce>(&unit, 1);
    step(full, tissue, inputs);
    for (int i = 0; i < 3; ++i) {
      const std::size_t at = 3 * static_cast<std::size_t>(a) + static_cast<std::size_t>(i);
      block(i, j) = tissue.positions_m[at] - rest[at];
    }
  }
  return block;
}

TEST(NeedleReducedCoupling, TheSolversComplianceIsHAInverseHTransposedPlusTheTissuesVVTransposed) {
  const Slab slab;
  const ReducedModel tissue =
      reduced_slab(slab, 16, ReducedForceKind::corotational_cubature, ReducedIntegrator::quasi_static);
  const ReducedCoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, slab_top_layer(0.001), tissue, slab.mesh, 32, 1).value();
  ReducedCoupledNeedleData data = make_coupled_needle_data(model, above_slab(0.0)).value();
  insert(model, data, 0.0, 0.012);
  ASSERT_GE(data.interaction.report.active_path_points, 4);
  const int rank = model.interaction.compliance_rank;
  const auto factors = [&](std::int32_t node) {  // node's 3 x rank rows of V
    return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        model.interaction.compliance_factors.data() +
            3 * static_cast<std::size_t>(node) * static_cast<std::size_t>(rank),
        3, rank);
  };
  const Eigen::MatrixXd dense = dense_compliance(
      model.interaction, data.interaction,
      [&](std::int32_t a, std::int32_t b) { return Eigen::Matrix3d(factors(a) * factors(b).transpose()); });
  bool symmetric = false;
  EXPECT_LT(compared_with_dense(data.interaction, dense, symmetric), 1e-10);
  EXPECT_TRUE(symmetric);
}

TEST(NeedleReducedCoupling, TheFullOrderSolversComplianceIsHAInverseHTransposedPlusTheSteppedNodeResponses) {
  // The full order through its nodes' responses (three solves with its rest factor per node):
  // its tissue block against the response of the tissue's own step, from rest, to a unit force
  // on each node along each axis (exact linear elements, quasi-static).
  const Slab slab;
  const TetFemModel full = make_tet_fem_model(slab.mesh, slab.scene, testing::exact_linear_options()).value();
  const CoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, slab_top_layer(0.001), full, 32, 1).value();
  CoupledNeedleData data = make_coupled_needle_data(model, above_slab(0.0)).value();
  insert(model, data, 0.0, 0.012);
  ASSERT_GE(data.interaction.report.active_path_points, 4);
  const Eigen::MatrixXd dense =
      dense_compliance(model.interaction, data.interaction,
                       [&](std::int32_t a, std::int32_t b) { return stepped_response_block(full, a, b); });
  bool symmetric = false;
  EXPECT_LT(compared_with_dense(data.interaction, dense, symmetric), 1e-9);
  EXPECT_TRUE(symmetric);
  EXPECT_TRUE(data.interaction.health.healthy());
}

TEST(NeedleReducedCoupling, MultiRateTissueKeepsThePuncture) {
  const Slab slab;
  const ReducedModel tissue =
      reduced_slab(slab, 16, ReducedForceKind::corotational_cubature, ReducedIntegrator::quasi_static);
  double at_m[2] = {0.0, 0.0};
  const int ratios[2] = {1, 10};
  for (int k = 0; k < 2; ++k) {
    const ReducedCoupledNeedleModel model =
        make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), tissue, slab.mesh, 32, ratios[k]).value();
    ReducedCoupledNeedleData data = make_coupled_needle_data(model, above_slab(0.0)).value();
    at_m[k] = insert(model, data, 0.0, 0.012);
    int points = 0;
    const double drag_m = mean_drag_m(data.interaction, data.displacements_m, points);
    std::printf(
        "tissue every %d ticks: puncture after lowering %.2f mm, %d path points, mean drag %.1f um, tissue steps "
        "%lld\n",
        ratios[k], 1e3 * at_m[k], points, 1e6 * drag_m, static_cast<long long>(data.tissue.steps));
    EXPECT_EQ(data.interaction.report.punctures, 1);
    EXPECT_GT(points, 0);
    EXPECT_GT(drag_m, 0.0);
    EXPECT_EQ(data.tissue.steps, data.ticks / ratios[k]);
    EXPECT_FALSE(data.interaction.health.has(HealthFlag::non_finite_state));
  }
  EXPECT_GT(at_m[0], 0.005);
  EXPECT_NEAR(at_m[1], at_m[0], 10 * testing::kInsertionStepM + 1e-9);
}

TEST(NeedleReducedCoupling, CoupledTicksAllocateNothingAndRepeatBitwise) {
  const Slab slab;
  const ReducedModel tissue =
      reduced_slab(slab, 16, ReducedForceKind::corotational_cubature, ReducedIntegrator::implicit_euler);
  const ReducedCoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), tissue, slab.mesh, 32, 3).value();
  std::uint64_t hashes[2] = {0, 0};
  for (std::uint64_t& hash : hashes) {
    ReducedCoupledNeedleData data = make_coupled_needle_data(model, above_slab(0.0)).value();
    testing::AllocationGuard guard;
    insert(model, data, 0.0, 0.01);
    EXPECT_EQ(guard.allocations(), 0u);
    EXPECT_EQ(data.interaction.report.punctures, 1);
    hash = testing::bits_hash({data.tissue.q, data.interaction.needle.positions_m});
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(NeedleReducedCoupling, TheMissingNodeComplianceMakesEachNodesComplianceTheFullOrders) {
  const Slab slab;
  const TetFemModel full = make_tet_fem_model(slab.mesh, slab.scene, testing::exact_linear_options()).value();
  const ReducedModel reduced = reduced_slab(slab, 6, ReducedForceKind::linear, ReducedIntegrator::quasi_static);
  const ReducedCoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), reduced, slab.mesh, 32, 1).value();
  // A radius below the 1 cm node spacing: each node's own block only.
  const auto missing = missing_node_compliance(factors_of(model.interaction), full, 0.005);
  ASSERT_TRUE(missing.ok()) << missing.error().describe();
  const std::size_t nodes = slab.mesh.nodes_m.size();
  ASSERT_EQ(missing.value().starts.size(), nodes + 1);
  const int r = model.interaction.compliance_rank;
  std::vector<double> response(3 * nodes), work(2 * static_cast<std::size_t>(full.free_dof_count()));
  double worst = 0.0, least_missed_share = 1.0;
  int free_nodes = 0;
  for (std::size_t n = 0; n < nodes; ++n) {
    const auto node = static_cast<std::int32_t>(n);
    const double* block = missing.value().find(node, node);
    Eigen::Matrix3d node_response;
    bool free = true;
    for (int axis = 0; axis < 3; ++axis) {
      free = rest_step_response_m(full, node, axis, response, work);
      node_response.col(axis) = Eigen::Map<const Eigen::Vector3d>(response.data() + 3 * n);
    }
    const std::int32_t entries = missing.value().starts[n + 1] - missing.value().starts[n];
    if (!free) {
      EXPECT_EQ(entries, 0) << "held node " << n;
      continue;
    }
    ASSERT_EQ(entries, 1) << "node " << n;
    ASSERT_NE(block, nullptr);
    ++free_nodes;
    const Eigen::Matrix3d local = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(block);
    const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> v(
        model.interaction.compliance_factors.data() + 3 * n * static_cast<std::size_t>(r), 3, r);
    worst = std::max(worst, (v * v.transpose() + local - node_response).norm() / node_response.norm());
    least_missed_share = std::min(least_missed_share, local.trace() / node_response.trace());
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(local).eigenvalues().minCoeff(), 0.0) << "node " << n;
  }
  std::printf(
      "%d free nodes: |V V^T + L - R| / |R| at most %.2e; the basis of 6 modes misses at least %.0f %% of a "
      "node's compliance\n",
      free_nodes, worst, 100.0 * least_missed_share);
  ASSERT_GT(free_nodes, 0);
  // Galerkin: the basis's compliance at a node is below the full order's, so nothing is clipped
  // and the sum is the full order's to rounding.
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(least_missed_share, 0.1);
}

TEST(NeedleReducedCoupling, WithTheMissingComplianceBetweenNodesTheSolversComplianceIsTheFullOrders) {
  // A truncated basis (6 modes) and the table of what it misses between nodes within 10 m (the
  // whole slab, where Wendland's taper is above 0.9996): the solver's W after an insertion
  // against the dense W of the full order's stepped node responses; within 3 cm (a taper of
  // 0.32 at 1.41 cm) the nodes further apart miss part of it.
  const Slab slab;
  const TetFemModel full = make_tet_fem_model(slab.mesh, slab.scene, testing::exact_linear_options()).value();
  const ReducedModel reduced = reduced_slab(slab, 6, ReducedForceKind::linear, ReducedIntegrator::quasi_static);
  ReducedCoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, slab_top_layer(0.001), reduced, slab.mesh, 32, 1).value();
  const auto stepped = [&](std::int32_t a, std::int32_t b) { return stepped_response_block(full, a, b); };
  double errors[2] = {0.0, 0.0};
  const double radii_m[2] = {10.0, 0.03};
  for (int k = 0; k < 2; ++k) {
    model.interaction.missing_compliance =
        missing_node_compliance(factors_of(model.interaction), full, radii_m[k]).value();
    ReducedCoupledNeedleData data = make_coupled_needle_data(model, above_slab(0.0)).value();
    insert(model, data, 0.0, 0.012);
    ASSERT_GE(data.interaction.report.active_path_points, 4);
    ASSERT_GE(data.interaction.distinct_tissue_node_count, 2);
    const Eigen::MatrixXd dense = dense_compliance(model.interaction, data.interaction, stepped);
    bool symmetric = false;
    errors[k] = compared_with_dense(data.interaction, dense, symmetric);
    EXPECT_TRUE(symmetric);
  }
  EXPECT_LT(errors[0], 1e-3);
  EXPECT_GT(errors[1], 10.0 * errors[0]);
}

TEST(NeedleReducedCoupling, ATruncatedBasisWithItsMissingNodeCompliancePuncturesAsTheFullOrder) {
  const Slab slab;
  const TetFemModel full = make_tet_fem_model(slab.mesh, slab.scene, testing::exact_linear_options()).value();
  const ReducedModel reduced = reduced_slab(slab, 6, ReducedForceKind::linear, ReducedIntegrator::quasi_static);
  NeedleTissueScene layer = slab_top_layer(0.01);
  layer.point_compliance_m_per_n = 1e-8;
  const CoupledNeedleModel full_model = make_coupled_needle_model(NeedleParameters{}, layer, full, 32, 1).value();
  ReducedCoupledNeedleModel truncated =
      make_coupled_needle_model(NeedleParameters{}, layer, reduced, slab.mesh, 32, 1).value();
  CoupledNeedleData full_data = make_coupled_needle_data(full_model, above_slab(0.0)).value();
  ReducedCoupledNeedleData without_data = make_coupled_needle_data(truncated, above_slab(0.0)).value();
  const double full_puncture_m = insert(full_model, full_data, 0.0, 0.02);
  const double without_m = insert(truncated, without_data, 0.0, 0.02);
  truncated.interaction.missing_compliance = missing_node_compliance(factors_of(truncated.interaction), full).value();
  ReducedCoupledNeedleData with_data = make_coupled_needle_data(truncated, above_slab(0.0)).value();
  testing::AllocationGuard guard;
  const double with_m = insert(truncated, with_data, 0.0, 0.02);
  EXPECT_EQ(guard.allocations(), 0u);
  std::printf(
      "puncture after lowering %.3f mm (full order), %.3f mm (6 modes), %.3f mm (6 modes and the missing "
      "node compliance)\n",
      1e3 * full_puncture_m, 1e3 * without_m, 1e3 * with_m);
  ASSERT_GT(full_puncture_m, 0.005);
  ASSERT_GT(without_m, 0.005);
  ASSERT_GT(with_m, 0.005);
  // The tip's one contact point on one node: its compliance is the full order's again, so the
  // puncture force builds over the same lowering (within 1 % and one tick); the truncated
  // basis alone is stiffer there and punctures sooner.
  EXPECT_NEAR(with_m, full_puncture_m, 0.01 * full_puncture_m + testing::kInsertionStepM);
  EXPECT_LT(without_m, full_puncture_m - 0.1 * (full_puncture_m - 0.005));
  EXPECT_LT(with_data.interaction.report.residual_m, truncated.interaction.scene.residual_bound_m);
}

TEST(NeedleReducedCoupling, BadCouplingsAreRefusedByName) {
  const Slab slab;
  const ReducedModel tissue = reduced_slab(slab, 8, ReducedForceKind::linear, ReducedIntegrator::quasi_static);
  const auto too_many = make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), tissue, slab.mesh, 33, 1);
  ASSERT_FALSE(too_many.ok());
  EXPECT_EQ(too_many.error().field, "max_point_forces");
  const TetMesh other = testing::box_mesh({kSideM, kSideM, kSideM}, 0.01);
  const auto wrong_mesh = make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), tissue, other, 32, 1);
  ASSERT_FALSE(wrong_mesh.ok());
  EXPECT_EQ(wrong_mesh.error().field, "mesh");
  const auto no_rate = make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), tissue, slab.mesh, 32, 0);
  ASSERT_FALSE(no_rate.ok());
  EXPECT_EQ(no_rate.error().field, "needle_steps_per_tissue_step");
  EXPECT_FALSE(reduced_compliance_factors(tissue, -1.0).ok());
  const auto coupled =
      make_coupled_needle_model(NeedleParameters{}, slab_top_layer(), tissue, slab.mesh, 32, 1).value();
  const TetFemModel cg = make_tet_fem_model(slab.mesh, slab.scene,
                                            [] {
                                              TissueSolverOptions o = testing::exact_linear_options();
                                              o.solver = LinearSolver::cg_jacobi;
                                              return o;
                                            }())
                             .value();
  const auto no_factor = missing_node_compliance(factors_of(coupled.interaction), cg);
  ASSERT_FALSE(no_factor.ok());
  EXPECT_EQ(no_factor.error().field, "full");
  const TetMesh tall = testing::box_mesh({kSideM, kSideM, kSideM}, 0.01);
  const TetFemModel other_full =
      make_tet_fem_model(tall, testing::held_at_bottom(tall), testing::exact_linear_options()).value();
  const auto other_mesh = missing_node_compliance(factors_of(coupled.interaction), other_full);
  ASSERT_FALSE(other_mesh.ok());
  EXPECT_EQ(other_mesh.error().field, "full");
  const TetFemModel exact = make_tet_fem_model(slab.mesh, slab.scene, testing::exact_linear_options()).value();
  const auto bad_radius = missing_node_compliance(factors_of(coupled.interaction), exact, -0.01);
  ASSERT_FALSE(bad_radius.ok());
  EXPECT_EQ(bad_radius.error().field, "radius_m");
}

}  // namespace
}  // namespace nav
