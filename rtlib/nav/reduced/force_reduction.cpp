// Energy-conserving sampling and weighting (ECSW) of the reduced internal forces, and the
// training envelope of a basis.
#include <algorithm>
#include <cmath>
#include <string>

#include "nav/reduced/full_system.hpp"
#include "nav/reduced/nnls.hpp"
#include "nav/reduced/reduced_forces.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/reduced/snapshots.hpp"
#include "nav/reduced/stvk_polynomial.hpp"

namespace nav {
namespace {

/// Most rows (r per snapshot) of the ECSW training matrix: its snapshots are spread evenly.
constexpr Eigen::Index kMaxTrainingRows = 512;

/// Reduced coordinates q = U^T M (u - L d) and diaphragm displacements of the snapshots.
struct TrainingStates {
  Eigen::MatrixXd q;  // r x snapshot_count
  Eigen::MatrixXd d;  // 3 x snapshot_count
};

Result<TrainingStates> training_states(const detail::FullSystem& system, const ReducedBasis& basis,
                                       std::span<const double> snapshots_m, int snapshot_count) {
  auto free = detail::free_snapshots(system, basis.diaphragm_lift, snapshots_m, snapshot_count);
  if (!free.ok()) return free.error();
  const detail::TetFemTables& tables = system.model.tables();
  const auto n3 = static_cast<std::size_t>(3 * tables.node_count);
  Eigen::MatrixXd u_free(system.mass_kg.size(), basis.basis_size);
  for (int j = 0; j < basis.basis_size; ++j)
    u_free.col(j) = detail::restrict_free(
        tables, std::span<const double>(basis.basis).subspan(static_cast<std::size_t>(j) * n3, n3));
  TrainingStates states{u_free.transpose() * system.mass_kg.asDiagonal() * free.value(),
                        Eigen::MatrixXd(3, snapshot_count)};
  for (int k = 0; k < snapshot_count; ++k)
    states.d.col(k) =
        detail::prescribed_displacement(tables, snapshots_m.subspan(n3 * static_cast<std::size_t>(k), n3));
  return states;
}

/// Reduced non-linear remainders U_e^T (f_e + K_e u_e) of the elements (samples of weight 1)
/// at `state`, into rows [row, row + r) of `columns`.
void element_forces(const detail::ReducedTables& t, const detail::ReducedState& state, Eigen::Index row,
                    Eigen::MatrixXd& columns) {
  constexpr std::size_t L = detail::kSampleLanes;
  const auto r = static_cast<std::size_t>(t.r);
  const std::size_t lanes = static_cast<std::size_t>(t.sample_blocks) * L;
  std::vector<double> displacements(12 * lanes), rotations(9 * lanes, 0.0), gradients(10 * lanes),
      lane_forces(r * lanes, 0.0);
  for (std::size_t k = 0; k < 3; ++k)
    std::fill_n(rotations.begin() + static_cast<std::ptrdiff_t>(4 * k * lanes), lanes, 1.0);
  const detail::SampleWork work{displacements.data(), rotations.data(), gradients.data(), lane_forces.data(), true};
  if (t.force_kind == ReducedForceKind::stvk_cubature)
    detail::add_stvk_forces(t, state, true, work);
  else
    detail::add_corotational_forces(t, state, true, work);  // a lane with det F <= 0 keeps the identity
  for (std::size_t e = 0; e < static_cast<std::size_t>(t.sample_count); ++e)
    for (std::size_t j = 0; j < r; ++j)
      columns(row + static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(e)) =
          lane_forces[(e / L * r + j) * L + e % L];
}

/// The largest error |residual_k| over the snapshot blocks of `block` rows (each block is
/// scaled by its snapshot's whole reduced force: a relative error).
double worst_relative_error(const Eigen::VectorXd& residual, Eigen::Index block) {
  double worst = 0.0;
  for (Eigen::Index k = 0; k + block <= residual.size(); k += block)
    worst = std::max(worst, residual.segment(k, block).norm());
  return worst;
}

/// ECSW: greedy selection of the element whose column best matches the residual, then NNLS
/// weights on the selection (warm-started from the last ones), until the relative training
/// error of every snapshot (blocks of `block` rows) is below the tolerance (at least one
/// element) or max_cubature_samples elements are chosen.
Status select_samples(const Eigen::MatrixXd& columns, const Eigen::VectorXd& target, Eigen::Index block,
                      const ReductionOptions& options, ReducedBasis& basis) {
  std::vector<Eigen::Index> selected;
  Eigen::VectorXd weights;
  Eigen::VectorXd residual = target;
  while ((selected.empty() || worst_relative_error(residual, block) > options.cubature_relative_tolerance) &&
         static_cast<int>(selected.size()) < options.max_cubature_samples) {
    const Eigen::VectorXd score = columns.transpose() * residual;
    Eigen::Index best = -1;
    for (Eigen::Index e = 0; e < columns.cols(); ++e)
      if (std::find(selected.begin(), selected.end(), e) == selected.end() && score[e] > 0.0 &&
          (best < 0 || score[e] > score[best]))
        best = e;
    if (best < 0) break;
    selected.push_back(best);
    Eigen::MatrixXd sub(columns.rows(), static_cast<Eigen::Index>(selected.size()));
    for (std::size_t k = 0; k < selected.size(); ++k) sub.col(static_cast<Eigen::Index>(k)) = columns.col(selected[k]);
    Eigen::VectorXd start = Eigen::VectorXd::Zero(sub.cols());  // the last weights, the new element at zero
    start.head(weights.size()) = weights;
    weights = detail::nnls(sub, target, start).x;
    residual = target - sub * weights;
  }
  if (selected.empty()) return field_error("no element reduces the training forces", "snapshots_m");
  basis.sample_tets.clear();
  basis.sample_weights.clear();
  std::vector<std::pair<Eigen::Index, double>> kept;
  for (std::size_t k = 0; k < selected.size(); ++k)
    if (weights[static_cast<Eigen::Index>(k)] > 0.0)
      kept.emplace_back(selected[k], weights[static_cast<Eigen::Index>(k)]);
  std::sort(kept.begin(), kept.end());
  for (const auto& [element, weight] : kept) {
    basis.sample_tets.push_back(static_cast<std::int32_t>(element));
    basis.sample_weights.push_back(weight);
  }
  return Done{};
}

/// The exact cubic polynomial of the reduced St Venant-Kirchhoff force.
Status add_polynomial(const detail::FullSystem& system, const TissueSolverOptions& solver, ReducedBasis& basis) {
  if (solver.law != ElementLaw::st_venant_kirchhoff)
    return field_error("the cubic polynomial needs the St Venant-Kirchhoff law", "law");
  if (solver.incompressibility_gain_pa != 0.0)
    return field_error("the incompressibility penalty is not a polynomial: the cubic polynomial needs it off",
                       "incompressibility_gain_pa");
  if (!basis.diaphragm_lift.empty())
    return field_error("the cubic polynomial force has no diaphragm lift", "prescribed_nodes");
  const auto n3 = 3 * static_cast<std::size_t>(basis.node_count);
  const auto r = static_cast<std::size_t>(basis.basis_size);
  std::vector<double> rows(n3 * r);
  for (std::size_t i = 0; i < n3; ++i)
    for (std::size_t j = 0; j < r; ++j) rows[i * r + j] = basis.basis[j * n3 + i];
  basis.polynomial_coefficients = detail::build_stvk_polynomial(system.model.tables(), rows, basis.basis_size);
  return Done{};
}

}  // namespace

Status add_force_reduction(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                           const ReductionOptions& options, std::span<const double> snapshots_m, int snapshot_count,
                           ReducedBasis& basis) {
  if (basis.mesh_fingerprint != mesh_fingerprint(mesh))
    return field_error("the basis belongs to another mesh", "mesh_fingerprint");
  if (options.max_cubature_samples < 1)
    return field_error("at least one cubature sample is needed", "max_cubature_samples");
  if (!(options.cubature_relative_tolerance >= 0.0))
    return field_error("the tolerance must be non-negative", "cubature_relative_tolerance");
  auto system = detail::make_full_system(mesh, scene, solver);
  if (!system.ok()) return system.error();
  if (basis.basis.size() != 3 * mesh.nodes_m.size() * static_cast<std::size_t>(std::max(basis.basis_size, 0)) ||
      basis.basis_size < 1)
    return field_error("the basis is not 3 node_count x basis_size", "basis");
  auto states = training_states(system.value(), basis, snapshots_m, snapshot_count);
  if (!states.ok()) return states.error();
  const Eigen::MatrixXd& q = states.value().q;
  basis.training_q_bound.assign(static_cast<std::size_t>(basis.basis_size), 0.0);
  for (int j = 0; j < basis.basis_size; ++j)
    basis.training_q_bound[static_cast<std::size_t>(j)] = q.row(j).cwiseAbs().maxCoeff();
  basis.training_residual_bound = 0.0;
  basis.sample_tets.clear();
  basis.sample_weights.clear();
  basis.polynomial_coefficients.clear();
  if (basis.force_kind == ReducedForceKind::linear) return Done{};
  if (basis.force_kind == ReducedForceKind::stvk_cubic_polynomial) return add_polynomial(system.value(), solver, basis);
  if (basis.force_kind == ReducedForceKind::stvk_cubature && solver.law != ElementLaw::st_venant_kirchhoff)
    return field_error("a St Venant-Kirchhoff cubature needs the St Venant-Kirchhoff law", "law");

  // Every element as a sample of weight 1: the tables the per-element forces are evaluated with.
  ReducedBasis every = basis;
  every.sample_tets.resize(mesh.tets.size());
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) every.sample_tets[e] = static_cast<std::int32_t>(e);
  every.sample_weights.assign(mesh.tets.size(), 1.0);
  every.training_q_bound.clear();
  auto full_model = make_reduced_model(mesh, scene, solver, every, ReducedSolverOptions{});
  if (!full_model.ok()) return full_model.error();
  const detail::ReducedTables& t = full_model.value().tables();

  const Eigen::Index r = basis.basis_size;
  const Eigen::Index used = std::max<Eigen::Index>(1, std::min<Eigen::Index>(snapshot_count, kMaxTrainingRows / r));
  const auto elements = static_cast<Eigen::Index>(mesh.tets.size());
  Eigen::MatrixXd columns = Eigen::MatrixXd::Zero(used * r, elements);
  for (Eigen::Index k = 0; k < used; ++k) {
    const Eigen::Index snapshot = used == 1 ? snapshot_count - 1 : k * (snapshot_count - 1) / (used - 1);
    const Eigen::VectorXd qs = q.col(snapshot);
    const Eigen::Vector3d ds = states.value().d.col(snapshot);
    const detail::ReducedState state{std::span<const double>(qs.data(), static_cast<std::size_t>(r)), ds.data()};
    element_forces(t, state, k * r, columns);
    // Every snapshot weighs the same: its rows are scaled by its whole reduced force, so that
    // the error is relative to that force (the remainder alone may be small).
    Eigen::VectorXd whole(r);
    detail::linear_force(t, state, std::span<double>(whole.data(), static_cast<std::size_t>(r)));
    whole += columns.middleRows(k * r, r).rowwise().sum();
    if (whole.norm() > 0.0) columns.middleRows(k * r, r) /= whole.norm();
  }
  const Eigen::VectorXd target = columns.rowwise().sum();
  if (!(target.norm() > 0.0))
    return field_error("the training snapshots have no non-linear force to reduce (use the linear force)",
                       "snapshots_m");
  if (auto s = select_samples(columns, target, r, options, basis); !s) return s;
  Eigen::VectorXd approximation = Eigen::VectorXd::Zero(target.size());
  for (std::size_t s = 0; s < basis.sample_tets.size(); ++s)
    approximation += basis.sample_weights[s] * columns.col(basis.sample_tets[s]);
  basis.training_residual_bound = worst_relative_error(approximation - target, r);
  return Done{};
}

}  // namespace nav
