// Init-time construction of a ReducedLadderModel (its rungs and transfer operators) and of
// its data.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "nav/reduced/reduced_ladder_tables.hpp"

namespace nav {
namespace {

using detail::ReducedLadderTables;

std::string rung_field(std::size_t i, const std::string& field) { return "rungs[" + std::to_string(i) + "]." + field; }

Status check_ladder_options(const ReducedLadderOptions& o) {
  if (o.escalate_after_steps < 1)
    return field_error("at least one flagged step must trigger an escalation", "escalate_after_steps");
  if (o.de_escalate_after_steps < 0)
    return field_error("the count must be 0 (never) or positive", "de_escalate_after_steps");
  if (!(o.de_escalation_envelope_ratio >= 0.0 && std::isfinite(o.de_escalation_envelope_ratio)))
    return field_error("the ratio must be a non-negative number", "de_escalation_envelope_ratio");
  if (!(o.de_escalation_residual >= 0.0 && std::isfinite(o.de_escalation_residual)))
    return field_error("the residual must be a non-negative number", "de_escalation_residual");
  return Done{};
}

/// Every rung shares the step and integrator of rung 0 and grows in r; a rung that may be
/// stepped down to has its envelope factor above the de-escalation ratio.
Status check_rungs(std::span<const ReducedRungSpec> rungs, bool full_order_on_top, const TissueSolverOptions& solver,
                   const ReducedLadderOptions& options) {
  if (rungs.empty()) return field_error("a ladder needs at least one reduced rung", "rungs");
  const ReducedSolverOptions& first = rungs[0].options;
  for (std::size_t i = 0; i < rungs.size(); ++i) {
    if (rungs[i].options.step_s != first.step_s)
      return field_error("every rung must have rung 0's step", rung_field(i, "options.step_s"));
    if (rungs[i].options.integrator != first.integrator)
      return field_error("every rung must have rung 0's integrator", rung_field(i, "options.integrator"));
    if (i > 0 && rungs[i].basis.basis_size <= rungs[i - 1].basis.basis_size)
      return field_error("basis sizes must grow strictly from rung to rung", rung_field(i, "basis.basis_size"));
    const bool below_another = i + 1 < rungs.size() || full_order_on_top;
    if (below_another && options.de_escalate_after_steps > 0 &&
        !(options.de_escalation_envelope_ratio < rungs[i].options.envelope_factor))
      return field_error("the de-escalation ratio must be below every lower rung's envelope factor",
                         "de_escalation_envelope_ratio");
  }
  if (!full_order_on_top) return Done{};
  if (solver.step_s != first.step_s)
    return field_error("the full order's step must be the reduced rungs' step", "step_s");
  const bool same_integrator =
      (first.integrator == ReducedIntegrator::implicit_euler && solver.integrator == Integrator::implicit_euler) ||
      (first.integrator == ReducedIntegrator::quasi_static && solver.integrator == Integrator::quasi_static);
  if (!same_integrator)
    return field_error("the full order's integrator must be the reduced rungs' (implicit Euler or quasi-static)",
                       "integrator");
  return Done{};
}

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::Map<const Eigen::MatrixXd> basis_of(const ReducedBasis& b) {
  return {b.basis.data(), 3 * static_cast<Eigen::Index>(b.node_count), b.basis_size};
}

/// U_big^T M U_small (row-major) and its loss 1 - min_j |T e_j|^2.
void add_transfer(const ReducedBasis& small, const ReducedBasis& big, const Eigen::VectorXd& mass,
                  ReducedLadderTables& t) {
  const RowMatrix transfer = basis_of(big).transpose() * mass.asDiagonal() * basis_of(small);
  double smallest = 1.0;
  for (Eigen::Index j = 0; j < transfer.cols(); ++j) smallest = std::min(smallest, transfer.col(j).squaredNorm());
  t.transfer.emplace_back(transfer.data(), transfer.data() + transfer.size());
  t.transfer_loss.push_back(1.0 - smallest);
}

/// The top reduced rung's basis and lift as row-major tables, and the dof masses.
void add_full_order_transfer(const ReducedBasis& top, const Eigen::VectorXd& mass, ReducedLadderTables& t) {
  const RowMatrix rows = basis_of(top);
  t.top_rows.assign(rows.data(), rows.data() + rows.size());
  if (!top.diaphragm_lift.empty()) {
    const RowMatrix lift = Eigen::Map<const Eigen::MatrixXd>(top.diaphragm_lift.data(), mass.size(), 3);
    t.lift_rows.assign(lift.data(), lift.data() + lift.size());
  }
  t.dof_mass_kg.assign(mass.data(), mass.data() + mass.size());
}

}  // namespace

int ReducedLadderModel::rung_count() const { return reduced_rung_count() + (has_full_order() ? 1 : 0); }
int ReducedLadderModel::reduced_rung_count() const { return static_cast<int>(tables_->rungs.size()); }
bool ReducedLadderModel::has_full_order() const { return tables_->full.has_value(); }
std::int64_t ReducedLadderModel::node_count() const { return tables_->node_count; }
const ReducedLadderOptions& ReducedLadderModel::options() const { return tables_->options; }
const ReducedModel& ReducedLadderModel::reduced_rung(int rung) const {
  return tables_->rungs[static_cast<std::size_t>(rung)];
}
const TetFemModel& ReducedLadderModel::full_order() const { return *tables_->full; }
double ReducedLadderModel::transfer_loss(int lower_rung) const {
  return tables_->transfer_loss[static_cast<std::size_t>(lower_rung)];
}
std::span<const double> ReducedLadderModel::transfer(int lower_rung) const {
  return tables_->transfer[static_cast<std::size_t>(lower_rung)];
}

Result<ReducedLadderModel> make_reduced_ladder_model(const TetMesh& mesh, const TissueScene& scene,
                                                     const TissueSolverOptions& solver,
                                                     std::span<const ReducedRungSpec> rungs, bool full_order_on_top,
                                                     const ReducedLadderOptions& options) {
  if (Status status = check_ladder_options(options); !status.ok()) return status.error();
  if (Status status = check_rungs(rungs, full_order_on_top, solver, options); !status.ok()) return status.error();
  // The full order's lumped masses give the transfers; without a full-order rung its rest
  // system is not factored (a Jacobi preconditioner costs nothing to build).
  TissueSolverOptions full_solver = solver;
  if (!full_order_on_top) full_solver.solver = LinearSolver::cg_jacobi;
  auto full = make_tet_fem_model(mesh, scene, full_solver);
  if (!full.ok()) return full.error();
  auto t = std::make_shared<ReducedLadderTables>();
  t->options = options;
  t->node_count = static_cast<std::int64_t>(mesh.nodes_m.size());
  for (std::size_t i = 0; i < rungs.size(); ++i) {
    auto model = make_reduced_model(mesh, scene, solver, rungs[i].basis, rungs[i].options);
    if (!model.ok()) {
      Error e = model.error();
      e.field = rung_field(i, e.field);
      return e;
    }
    t->rungs.push_back(std::move(model).value());
    t->sizes.push_back(rungs[i].basis.basis_size);
    t->q_bound.push_back(rungs[i].basis.training_q_bound);
    t->max_r = std::max(t->max_r, rungs[i].basis.basis_size);
  }
  const auto masses = full.value().nodal_masses_kg();
  Eigen::VectorXd mass(3 * static_cast<Eigen::Index>(masses.size()));
  for (Eigen::Index k = 0; k < mass.size(); ++k) mass[k] = masses[static_cast<std::size_t>(k / 3)];
  for (std::size_t i = 0; i + 1 < rungs.size(); ++i) add_transfer(rungs[i].basis, rungs[i + 1].basis, mass, *t);
  if (full_order_on_top) {
    add_full_order_transfer(rungs.back().basis, mass, *t);
    t->full = std::move(full).value();
  }
  return ReducedLadderModel(std::move(t));
}

Result<ReducedLadderData> make_reduced_ladder_data(const ReducedLadderModel& model) {
  const ReducedLadderTables& t = model.tables();
  const auto r = static_cast<std::size_t>(t.max_r);
  ReducedLadderData data(Arena("reduced_ladder_data", ArenaPlan().add<double>(4 * r).bytes()));
  std::span<double>* vectors[] = {&data.saved_q, &data.saved_velocity, &data.projected_q, &data.projected_velocity};
  for (std::span<double>* vector : vectors) {
    auto carved = data.arena.allocate<double>("ladder vector", r);
    if (!carved.ok()) return carved.error();
    *vector = carved.value();
  }
  data.reduced.reserve(t.rungs.size());
  for (const ReducedModel& rung : t.rungs) {
    auto rung_data = make_reduced_data(rung);
    if (!rung_data.ok()) return rung_data.error();
    data.reduced.push_back(std::move(rung_data).value());
  }
  if (t.full) {
    auto full_data = make_tet_fem_data(*t.full);
    if (!full_data.ok()) return full_data.error();
    data.full.emplace(std::move(full_data).value());
  }
  return data;
}

}  // namespace nav
