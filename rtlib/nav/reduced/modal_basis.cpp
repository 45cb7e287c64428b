// Vibration modes by shift-invert Lanczos (Spectra) and their St Venant-Kirchhoff modal
// derivatives.
#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <string>

#include "nav/reduced/basis_tools.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/sparse_cholesky.hpp"
#include "nav/tissue/tet_kernels.hpp"

namespace nav {
namespace {

using detail::FullSystem;
using detail::TetFemTables;
using SparseMatrix = Eigen::SparseMatrix<double>;

/// (K - sigma M)^-1 x for Spectra (SparseCholesky).
class ShiftInvertOperator {
 public:
  using Scalar = double;
  ShiftInvertOperator(const SparseMatrix& stiffness, const SparseMatrix& mass) : stiffness_(stiffness), mass_(mass) {}
  Eigen::Index rows() const { return stiffness_.rows(); }
  Eigen::Index cols() const { return stiffness_.cols(); }
  void set_shift(double sigma) {
    factored_ = factor_.factor(SparseMatrix(stiffness_ - sigma * mass_), "stiffness").ok();
  }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<Eigen::VectorXd>(y_out, rows()) = factor_.solve(Eigen::Map<const Eigen::VectorXd>(x_in, rows()));
  }
  bool factored() const { return factored_; }

 private:
  const SparseMatrix& stiffness_;
  const SparseMatrix& mass_;
  SparseCholesky factor_;
  bool factored_ = false;
};

/// The shift: below zero so that K - sigma M stays positive definite for a body held by
/// nothing (its rigid motions are then modes of w^2 = 0), far below the first elastic w^2.
constexpr double kShift = -1.0;

/// The `count` lowest modes (free-dof columns) and their w^2.
Result<std::pair<Eigen::MatrixXd, Eigen::VectorXd>> lowest_modes(const FullSystem& system, Eigen::Index count) {
  const Eigen::Index n = system.stiffness.rows();
  SparseMatrix mass(n, n);
  std::vector<Eigen::Triplet<double>> diagonal;
  for (Eigen::Index i = 0; i < n; ++i) diagonal.emplace_back(i, i, system.mass_kg[i]);
  mass.setFromTriplets(diagonal.begin(), diagonal.end());
  ShiftInvertOperator op(system.stiffness, mass);
  Spectra::SparseSymMatProd<double> mass_op(mass);
  const Eigen::Index ncv = std::min(n, std::max<Eigen::Index>(2 * count + 1, count + 8));
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  if (count >= n || ncv <= count) {  // a complete basis, or nearly: a dense solve
    const Eigen::MatrixXd dense(system.stiffness);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(dense, Eigen::MatrixXd(mass));
    if (solver.info() != Eigen::Success) return field_error("the dense eigen solver failed", "basis_size");
    values = solver.eigenvalues().head(count);
    vectors = solver.eigenvectors().leftCols(count);
  } else {
    Spectra::SymGEigsShiftSolver<ShiftInvertOperator, Spectra::SparseSymMatProd<double>,
                                 Spectra::GEigsMode::ShiftInvert>
        solver(op, mass_op, count, ncv, kShift);
    if (!op.factored()) return field_error("the shifted stiffness cannot be factored", "fixed_nodes");
    solver.init();
    solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-12, Spectra::SortRule::SmallestAlge);
    if (solver.info() != Spectra::CompInfo::Successful)
      return field_error("the Lanczos iteration did not converge", "basis_size");
    values = solver.eigenvalues();
    vectors = solver.eigenvectors();
  }
  return std::pair{std::move(vectors), std::move(values)};
}

/// Second directional derivative of the St Venant-Kirchhoff first Piola stress at rest
/// along displacement gradients a and b: a C(sym b) + b C(sym a) + C(sym(a^T b)).
Eigen::Matrix3d stvk_second_derivative(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, const LameParameters& lame) {
  auto elastic = [&](const Eigen::Matrix3d& h) {
    const Eigen::Matrix3d strain = 0.5 * (h + h.transpose());
    Eigen::Matrix3d stress = (2.0 * lame.mu_pa) * strain;
    stress.diagonal().array() += lame.lambda_pa * strain.trace();
    return stress;
  };
  return a * elastic(b) + b * elastic(a) + elastic(a.transpose() * b);
}

/// The free-dof vector d^2 f_int [phi_i, phi_j] of the St Venant-Kirchhoff forces at rest.
Eigen::VectorXd force_second_derivative(const TetFemTables& tables, const Eigen::VectorXd& full_i,
                                        const Eigen::VectorXd& full_j) {
  Eigen::VectorXd force = Eigen::VectorXd::Zero(3 * tables.node_count);
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero(), b = Eigen::Matrix3d::Zero();
    for (int v = 0; v < 4; ++v) {
      const Eigen::Vector3d g(tables.gradients.data() + 12 * e + 3 * v);
      const Eigen::Index node = tables.tets[e][v];
      a += full_i.segment<3>(3 * node) * g.transpose();
      b += full_j.segment<3>(3 * node) * g.transpose();
    }
    const Eigen::Matrix3d stress = stvk_second_derivative(a, b, tables.lame[e]);
    for (int v = 0; v < 4; ++v) {
      const Eigen::Vector3d g(tables.gradients.data() + 12 * e + 3 * v);
      force.segment<3>(3 * tables.tets[e][v]) -= tables.volume_m3[e] * (stress * g);
    }
  }
  return force;
}

/// Modes and their modal derivatives K^-1 d^2 f [phi_i, phi_j] (i <= j), in that order.
Result<Eigen::MatrixXd> with_modal_derivatives(const FullSystem& system, const Eigen::MatrixXd& modes) {
  const TetFemTables& tables = system.model.tables();
  SparseCholesky factor;
  if (!factor.factor(system.stiffness, "stiffness").ok())
    return field_error("modal derivatives need a stiffness made regular by fixed nodes, springs or a prescribed region",
                       "fixed_nodes");
  const Eigen::Index k = modes.cols();
  Eigen::MatrixXd columns(modes.rows(), k + k * (k + 1) / 2);
  columns.leftCols(k) = modes;
  Eigen::Index next = k;
  std::vector<Eigen::VectorXd> full(static_cast<std::size_t>(k));
  for (Eigen::Index i = 0; i < k; ++i) full[static_cast<std::size_t>(i)] = detail::expand_free(tables, modes.col(i));
  for (Eigen::Index j = 0; j < k; ++j)
    for (Eigen::Index i = 0; i <= j; ++i) {
      const Eigen::VectorXd force =
          force_second_derivative(tables, full[static_cast<std::size_t>(i)], full[static_cast<std::size_t>(j)]);
      columns.col(next++) = factor.solve(
          detail::restrict_free(tables, std::span<const double>(force.data(), static_cast<std::size_t>(force.size()))));
    }
  return columns;
}

}  // namespace

Result<ReducedBasis> make_modal_basis(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                                      const ReductionOptions& options) {
  if (options.source == ReducedBasisSource::pod) return field_error("a POD basis is built by make_pod_basis", "source");
  auto system = detail::make_full_system(mesh, scene, solver);
  if (!system.ok()) return system.error();
  const Eigen::Index free_dofs = system.value().stiffness.rows();
  if (options.basis_size < 1 || options.basis_size > free_dofs)
    return field_error("the basis size must be between 1 and the " + std::to_string(free_dofs) + " free dofs",
                       "basis_size");
  const bool derivatives = options.source == ReducedBasisSource::modal_derivatives;
  Eigen::Index mode_count = options.basis_size;
  if (derivatives) {  // k modes give k (k + 3) / 2 columns before orthonormalisation
    mode_count = 1;
    while (mode_count * (mode_count + 3) / 2 < options.basis_size) ++mode_count;
    mode_count = std::min(mode_count, free_dofs);
  }
  auto modes = lowest_modes(system.value(), mode_count);
  if (!modes.ok()) return modes.error();
  auto& [vectors, values] = modes.value();
  Eigen::MatrixXd columns = vectors;
  if (derivatives) {
    auto extended = with_modal_derivatives(system.value(), vectors);
    if (!extended.ok()) return extended.error();
    columns = std::move(extended).value();
  }
  constexpr double kDropFraction = 1e-8;
  const Eigen::MatrixXd basis_columns =
      detail::mass_orthonormalize(columns, system.value().mass_kg, kDropFraction, options.basis_size);
  if (basis_columns.cols() < options.basis_size)
    return field_error(
        "the modes and their derivatives span only " + std::to_string(basis_columns.cols()) + " directions",
        "basis_size");
  auto basis = detail::pack_basis(mesh, system.value(), basis_columns, options.source, options.force_kind);
  if (!basis.ok()) return basis;
  for (Eigen::Index c = 0; c < std::min<Eigen::Index>(values.size(), options.basis_size); ++c)
    basis.value().column_values[static_cast<std::size_t>(c)] = values[c];
  if (derivatives)  // past the modes, the columns are derivatives: no frequency
    std::fill(basis.value().column_values.begin() + mode_count, basis.value().column_values.end(), 0.0);
  return basis;
}

}  // namespace nav
