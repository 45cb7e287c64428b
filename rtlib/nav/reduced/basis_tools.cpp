#include "nav/reduced/basis_tools.hpp"

#include <cmath>

namespace nav::detail {

Eigen::MatrixXd mass_orthonormalize(const Eigen::MatrixXd& candidates, const Eigen::VectorXd& mass_kg,
                                    double drop_fraction, Eigen::Index max_columns) {
  Eigen::MatrixXd kept(candidates.rows(), std::min(max_columns, candidates.cols()));
  Eigen::Index count = 0;
  for (Eigen::Index c = 0; c < candidates.cols() && count < kept.cols(); ++c) {
    Eigen::VectorXd v = candidates.col(c);
    const double original = std::sqrt(v.dot(mass_kg.cwiseProduct(v)));
    if (!(original > 0.0)) continue;
    for (int pass = 0; pass < 2; ++pass)
      for (Eigen::Index k = 0; k < count; ++k) v -= kept.col(k).dot(mass_kg.cwiseProduct(v)) * kept.col(k);
    const double remaining = std::sqrt(v.dot(mass_kg.cwiseProduct(v)));
    if (!(remaining > drop_fraction * original)) continue;
    kept.col(count++) = v / remaining;
  }
  return kept.leftCols(count);
}

Result<ReducedBasis> pack_basis(const TetMesh& mesh, const FullSystem& system, const Eigen::MatrixXd& columns,
                                ReducedBasisSource source, ReducedForceKind force_kind) {
  const TetFemTables& tables = system.model.tables();
  ReducedBasis basis;
  basis.mesh_fingerprint = mesh_fingerprint(mesh);
  basis.node_count = static_cast<std::int32_t>(tables.node_count);
  basis.basis_size = static_cast<std::int32_t>(columns.cols());
  basis.source = source;
  basis.force_kind = force_kind;
  const auto n3 = static_cast<std::size_t>(3 * tables.node_count);
  basis.basis.assign(n3 * static_cast<std::size_t>(columns.cols()), 0.0);
  for (Eigen::Index c = 0; c < columns.cols(); ++c) {
    const Eigen::VectorXd full = expand_free(tables, columns.col(c));
    std::copy(full.data(), full.data() + full.size(), basis.basis.begin() + static_cast<std::ptrdiff_t>(c * n3));
  }
  basis.column_values.assign(static_cast<std::size_t>(columns.cols()), 0.0);
  auto lift = diaphragm_lift(system);
  if (!lift.ok()) return lift.error();
  basis.diaphragm_lift = std::move(lift).value();
  return basis;
}

}  // namespace nav::detail
