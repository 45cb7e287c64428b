// Init-time construction of a ReducedModel and its data.
#include <algorithm>
#include <cmath>
#include <string>

#include "nav/core/finite.hpp"
#include "nav/reduced/dense_cholesky.hpp"
#include "nav/reduced/full_system.hpp"
#include "nav/reduced/reduced_forces.hpp"
#include "nav/reduced/reduced_kernels.hpp"
#include "nav/reduced/reduced_tables.hpp"
#include "nav/reduced/stvk_polynomial.hpp"
#include "nav/tissue/tet_kernels.hpp"

namespace nav {
namespace {

using detail::ReducedTables;
using detail::TetFemTables;

Status check_options(const ReducedSolverOptions& o) {
  if (!(std::isfinite(o.step_s) && o.step_s > 0.0))
    return field_error("the step must be a positive number of seconds", "step_s");
  if (o.newton_iterations < 1) return field_error("at least one Newton iteration is needed", "newton_iterations");
  if (!(o.rayleigh_mass_per_s >= 0.0 && std::isfinite(o.rayleigh_mass_per_s)))
    return field_error("Rayleigh damping must be a non-negative number", "rayleigh_mass_per_s");
  if (!(o.rayleigh_stiffness_s >= 0.0 && std::isfinite(o.rayleigh_stiffness_s)))
    return field_error("Rayleigh damping must be a non-negative number", "rayleigh_stiffness_s");
  if (!(o.envelope_factor > 0.0 && std::isfinite(o.envelope_factor)))
    return field_error("the envelope factor must be a positive number", "envelope_factor");
  if (!(o.error_bound_m > 0.0 && std::isfinite(o.error_bound_m)))
    return field_error("the error bound must be a positive number of metres", "error_bound_m");
  if (!kernel_isa_available(o.kernel_isa))
    return field_error("this build or CPU has no " + std::string(kernel_isa_name(o.kernel_isa)) + " kernels",
                       "kernel_isa");
  return Done{};
}

Status check_basis(const TetMesh& mesh, const ReducedBasis& b) {
  const auto n3 = 3 * mesh.nodes_m.size();
  const auto r = static_cast<std::size_t>(b.basis_size);
  if (b.mesh_fingerprint != mesh_fingerprint(mesh))
    return field_error("the basis belongs to another mesh", "mesh_fingerprint");
  if (b.node_count != static_cast<std::int32_t>(mesh.nodes_m.size()))
    return field_error("the node count differs from the mesh's", "node_count");
  if (b.basis_size < 1 || b.basis.size() != n3 * r)
    return field_error("the basis is not 3 node_count x basis_size", "basis");
  if (!b.diaphragm_lift.empty() && b.diaphragm_lift.size() != 3 * n3)
    return field_error("the lift is not 3 node_count x 3", "diaphragm_lift");
  if (b.sample_tets.size() != b.sample_weights.size())
    return field_error("one weight per sampled tetrahedron is needed", "sample_weights");
  for (std::size_t s = 0; s < b.sample_tets.size(); ++s) {
    if (b.sample_tets[s] < 0 || static_cast<std::size_t>(b.sample_tets[s]) >= mesh.tets.size())
      return field_error("sample " + std::to_string(s) + " is not a tetrahedron of the mesh", "sample_tets");
    if (!(b.sample_weights[s] >= 0.0 && std::isfinite(b.sample_weights[s])))
      return field_error("sample " + std::to_string(s) + " has a negative or non-finite weight", "sample_weights");
  }
  const bool cubature =
      b.force_kind == ReducedForceKind::corotational_cubature || b.force_kind == ReducedForceKind::stvk_cubature;
  if (cubature && b.sample_tets.empty()) return field_error("a cubature force needs sampled tetrahedra", "sample_tets");
  if (b.force_kind == ReducedForceKind::stvk_cubic_polynomial) {
    if (b.polynomial_coefficients.size() != detail::stvk_polynomial_size(b.basis_size))
      return field_error(
          "the cubic polynomial needs " + std::to_string(detail::stvk_polynomial_size(b.basis_size)) + " coefficients",
          "polynomial_coefficients");
    if (!b.diaphragm_lift.empty())
      return field_error("the cubic polynomial force has no diaphragm lift", "diaphragm_lift");
  }
  if (!b.training_q_bound.empty() && b.training_q_bound.size() != r)
    return field_error("one bound per column is needed", "training_q_bound");
  for (double value : b.basis)
    if (!std::isfinite(value)) return field_error("the basis has a non-finite value", "basis");
  return Done{};
}

/// Rows (3 x r) of `node` of the column-major basis, appended to `out`.
void append_rows(const ReducedBasis& b, std::int64_t node, std::vector<double>& out) {
  const auto n3 = static_cast<std::size_t>(3 * b.node_count);
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < b.basis_size; ++j)
      out.push_back(b.basis[static_cast<std::size_t>(j) * n3 + 3 * static_cast<std::size_t>(node) + c]);
}

void append_lift_rows(const ReducedBasis& b, std::int64_t node, std::vector<double>& out) {
  const auto n3 = static_cast<std::size_t>(3 * b.node_count);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k)
      out.push_back(b.diaphragm_lift[static_cast<std::size_t>(k) * n3 + 3 * static_cast<std::size_t>(node) + c]);
}

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// U^T M U, U^T K U, U^T K L, U^T M g and the traction shares.
Status build_projections(const TetFemTables& full, ReducedTables& t) {
  const int r = t.r;
  const Eigen::Map<const RowMatrix> u(t.rows.data(), 3 * full.node_count, r);
  Eigen::MatrixXd mass_r = Eigen::MatrixXd::Zero(r, r), stiffness = Eigen::MatrixXd::Zero(r, r),
                  lift = Eigen::MatrixXd::Zero(r, 3);
  for (std::int64_t node = 0; node < full.node_count; ++node) {
    const auto block = u.middleRows(3 * node, 3);
    mass_r += full.mass_kg[static_cast<std::size_t>(node)] * block.transpose() * block;
  }
  if ((mass_r - Eigen::MatrixXd::Identity(r, r)).cwiseAbs().maxCoeff() > 1e-6)
    return field_error("the basis is not mass-orthonormal (U^T M U differs from I by more than 1e-6)", "basis");
  for (std::size_t e = 0; e < full.tets.size(); ++e) {
    Matrix43 gradients;
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c) gradients(a, c) = full.gradients[12 * e + 3 * a + c];
    const Matrix12 ke = element_stiffness(gradients, full.lame[e], full.volume_m3[e]);
    Eigen::Matrix<double, 12, Eigen::Dynamic> ue(12, r);
    Eigen::Matrix<double, 12, 3> le = Eigen::Matrix<double, 12, 3>::Zero();
    for (int a = 0; a < 4; ++a) {
      const std::int64_t node = full.tets[e][a];
      ue.middleRows<3>(3 * a) = u.middleRows(3 * node, 3);
      if (t.has_lift)
        le.middleRows<3>(3 * a) =
            Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(t.lift_rows.data() + 9 * node);
    }
    const Eigen::MatrixXd kue = ke * ue;
    stiffness += ue.transpose() * kue;
    lift += kue.transpose() * le;
  }
  stiffness = 0.5 * (stiffness + stiffness.transpose()).eval();
  t.stiffness_r.resize(static_cast<std::size_t>(r * r));
  Eigen::Map<RowMatrix>(t.stiffness_r.data(), r, r) = stiffness;
  t.stiffness_lift_r.resize(static_cast<std::size_t>(3 * r));
  Eigen::Map<RowMatrix>(t.stiffness_lift_r.data(), r, 3) = lift;
  Eigen::VectorXd gravity = Eigen::VectorXd::Zero(r);
  for (std::int64_t node = 0; node < full.node_count; ++node)
    for (int c = 0; c < 3; ++c)
      gravity += full.mass_kg[static_cast<std::size_t>(node)] * full.gravity_m_s2[c] * u.row(3 * node + c).transpose();
  t.gravity_r.assign(gravity.data(), gravity.data() + r);
  t.traction_r.assign(static_cast<std::size_t>(3 * r), 0.0);
  for (std::size_t k = 0; k < full.traction_nodes.size(); ++k)
    for (int c = 0; c < 3; ++c)
      for (int j = 0; j < r; ++j)
        t.traction_r[static_cast<std::size_t>(c * r + j)] +=
            full.traction_area_m2[k] * u(3 * full.traction_nodes[k] + c, j);
  return Done{};
}

void build_springs(const TetFemTables& full, ReducedTables& t) {
  const int r = t.r;
  t.spring_stiffness_n_m = full.spring_stiffness_n_m;
  Eigen::MatrixXd springs = Eigen::MatrixXd::Zero(r, r);
  const Eigen::Map<const RowMatrix> u(t.rows.data(), 3 * full.node_count, r);
  for (std::int32_t node : full.spring_nodes) {
    if (full.free_index[static_cast<std::size_t>(node)] < 0) continue;
    t.spring_nodes.push_back(node);
    for (int c = 0; c < 3; ++c) t.spring_rest_m.push_back(full.rest_m[3 * static_cast<std::size_t>(node) + c]);
    springs += full.spring_stiffness_n_m * u.middleRows(3 * node, 3).transpose() * u.middleRows(3 * node, 3);
  }
  t.spring_stiffness_r.resize(static_cast<std::size_t>(r * r));
  Eigen::Map<RowMatrix>(t.spring_stiffness_r.data(), r, r) = springs;
}

/// The error estimate's tables (reduced_tables.hpp) from the basis's calibration; nothing
/// without one. Errors name the calibration's field.
Status build_error_estimate(const ReducedBasis& b, ReducedTables& t) {
  const ReducedErrorCalibration& c = b.error_calibration;
  if (c.missing_compliance_m_per_n.empty()) return Done{};
  if (c.missing_compliance_m_per_n.size() != 6 * static_cast<std::size_t>(t.node_count))
    return field_error("the missing compliance is not 6 values per node",
                       "error_calibration.missing_compliance_m_per_n");
  if (!all_finite(c.missing_compliance_m_per_n))
    return field_error("the missing compliance has a non-finite value", "error_calibration.missing_compliance_m_per_n");
  if (!(c.gain > 0.0 && std::isfinite(c.gain)))
    return field_error("the error estimate's gain must be a positive number", "error_calibration.gain");
  t.missing_compliance = c.missing_compliance_m_per_n;
  t.error_gain = c.gain;
  t.error_bound_m = t.options.error_bound_m;
  return Done{};
}

/// The sampled tetrahedra's tables, blocked by kSampleLanes (see ReducedTables), and the
/// linear stiffness they take back out: K_S = sum w U_s^T K_s U_s, K_Sl = sum w U_s^T K_s L_s.
void build_samples(const TetFemTables& full, const ReducedBasis& b, ReducedTables& t) {
  constexpr int L = detail::kSampleLanes;
  const int r = t.r;
  t.sample_count = static_cast<int>(b.sample_tets.size());
  t.sample_blocks = (t.sample_count + L - 1) / L;
  const auto lanes = static_cast<std::size_t>(t.sample_blocks) * L;
  t.sample_rows.assign(lanes * 12 * static_cast<std::size_t>(r), 0.0);
  if (t.has_lift) t.sample_lift.assign(lanes * 36, 0.0);
  t.sample_rest_m.assign(lanes * 12, 0.0);
  t.sample_gradients.assign(lanes * 12, 0.0);
  t.sample_root_stiffness.assign(lanes * 72, 0.0);
  t.sample_weight_volume.assign(lanes, 0.0);
  t.sample_lame.assign(lanes, LameParameters{0.0, 0.0});
  // Value x (of `per_sample`) of sample s.
  auto at = [](std::size_t s, int per_sample, int x) {
    return ((s / L) * static_cast<std::size_t>(per_sample) + static_cast<std::size_t>(x)) * L + s % L;
  };
  Eigen::MatrixXd rest_tangent = Eigen::MatrixXd::Zero(r, r), rest_lift = Eigen::MatrixXd::Zero(r, 3);
  for (std::size_t s = 0; s < b.sample_tets.size(); ++s) {
    const auto e = static_cast<std::size_t>(b.sample_tets[s]);
    Eigen::Matrix<double, 12, Eigen::Dynamic> rows(12, r);
    Eigen::Matrix<double, 12, 3> lift = Eigen::Matrix<double, 12, 3>::Zero();
    for (int a = 0; a < 4; ++a) {
      const std::int64_t node = full.tets[e][a];
      for (int c = 0; c < 3; ++c) {
        const int i = 3 * a + c;
        for (int j = 0; j < r; ++j) {
          rows(i, j) = t.rows[static_cast<std::size_t>((3 * node + c) * r + j)];
          t.sample_rows[at(s, 12 * r, r * i + j)] = rows(i, j);
        }
        for (int k = 0; k < 3 && t.has_lift; ++k) {
          lift(i, k) = t.lift_rows[static_cast<std::size_t>(9 * node + 3 * c + k)];
          t.sample_lift[at(s, 36, 3 * i + k)] = lift(i, k);
        }
        t.sample_rest_m[at(s, 12, i)] = full.rest_m[3 * static_cast<std::size_t>(node) + static_cast<std::size_t>(c)];
      }
    }
    Matrix43 gradients;
    for (int k = 0; k < 12; ++k) {
      t.sample_gradients[at(s, 12, k)] = full.gradients[12 * e + static_cast<std::size_t>(k)];
      gradients(k / 3, k % 3) = full.gradients[12 * e + static_cast<std::size_t>(k)];
    }
    const double weight_volume = b.sample_weights[s] * full.volume_m3[e];
    t.sample_weight_volume[at(s, 1, 0)] = weight_volume;
    t.sample_lame[s] = full.lame[e];
    // K_e = V B^T D B = G^T G with G = sqrt(V) L^T B, D = L L^T.
    const Matrix6 root = Eigen::LLT<Matrix6>(elasticity_matrix(full.lame[e])).matrixU();
    const Matrix6x12 g = std::sqrt(weight_volume) * root * strain_displacement(gradients);
    for (int i = 0; i < 6; ++i)
      for (int k = 0; k < 12; ++k) t.sample_root_stiffness[at(s, 72, 12 * i + k)] = g(i, k);
    const Eigen::MatrixXd v = g * rows;
    rest_tangent += v.transpose() * v;
    rest_lift += v.transpose() * (g * lift);
  }
  rest_tangent = 0.5 * (rest_tangent + rest_tangent.transpose()).eval();
  t.sample_rest_tangent_r.resize(static_cast<std::size_t>(r * r));
  Eigen::Map<RowMatrix>(t.sample_rest_tangent_r.data(), r, r) = rest_tangent;
  t.cubature_stiffness_r.resize(static_cast<std::size_t>(r * r));
  for (std::size_t i = 0; i < t.cubature_stiffness_r.size(); ++i)
    t.cubature_stiffness_r[i] = t.stiffness_r[i] - t.sample_rest_tangent_r[i];
  t.cubature_stiffness_lift_r.assign(static_cast<std::size_t>(3 * r), 0.0);
  for (int i = 0; i < r; ++i)
    for (int k = 0; k < 3; ++k)
      t.cubature_stiffness_lift_r[static_cast<std::size_t>(3 * i + k)] =
          t.stiffness_lift_r[static_cast<std::size_t>(3 * i + k)] - rest_lift(i, k);
}

/// The frozen system matrix, factored: see detail::system_coefficients.
Status build_frozen_factor(ReducedTables& t) {
  const detail::SystemCoefficients c = detail::system_coefficients(t.options);
  t.frozen_factor.resize(static_cast<std::size_t>(t.r * t.r));
  detail::system_matrix(t.stiffness_r, t.spring_stiffness_r, c.identity, c.stiffness, c.spring, t.r, t.frozen_factor);
  if (!detail::cholesky_in_place(t.frozen_factor, t.r)) {
    const bool implicit = t.options.integrator == ReducedIntegrator::implicit_euler;
    return field_error(implicit
                           ? "the reduced system is not positive definite"
                           : "the quasi-static reduced system is singular: the scene needs fixed nodes, springs or a "
                             "prescribed region",
                       implicit ? "step_s" : "fixed_nodes");
  }
  return Done{};
}

}  // namespace

Result<ReducedModel> make_reduced_model(const TetMesh& mesh, const TissueScene& scene,
                                        const TissueSolverOptions& solver, const ReducedBasis& basis,
                                        const ReducedSolverOptions& options) {
  if (auto s = check_options(options); !s) return s.error();
  if (auto s = check_basis(mesh, basis); !s) return s.error();
  if (scene.probe_stiffness_n_m > 0.0)
    return field_error("the reduced model has no probe contact", "probe_stiffness_n_m");
  if (scene.point_force_own_share != 1.0)
    return field_error("the reduced model keeps point forces on their nodes", "point_force_own_share");
  auto system = detail::make_full_system(mesh, scene, solver);
  if (!system.ok()) return system.error();
  const TetFemTables& full = system.value().model.tables();
  if (full.prescribed_nodes.empty() != basis.diaphragm_lift.empty())
    return field_error("the lift must be present exactly when the scene prescribes nodes", "diaphragm_lift");
  auto t = std::make_shared<ReducedTables>();
  t->options = options;
  t->lane_kernels = &detail::reduced_lane_kernels(options.kernel_isa);
  t->force_kind = basis.force_kind;
  t->r = basis.basis_size;
  t->node_count = full.node_count;
  t->has_lift = !basis.diaphragm_lift.empty();
  t->max_point_forces = full.max_point_forces;
  t->gain_pa = solver.law == ElementLaw::st_venant_kirchhoff ? solver.incompressibility_gain_pa : 0.0;
  t->rows.reserve(basis.basis.size());
  for (std::int64_t node = 0; node < full.node_count; ++node) {
    append_rows(basis, node, t->rows);
    if (t->has_lift) append_lift_rows(basis, node, t->lift_rows);
  }
  if (auto s = build_projections(full, *t); !s) return s.error();
  build_springs(full, *t);
  if (basis.force_kind == ReducedForceKind::corotational_cubature ||
      basis.force_kind == ReducedForceKind::stvk_cubature)
    build_samples(full, basis, *t);
  if (basis.force_kind == ReducedForceKind::stvk_cubic_polynomial) t->polynomial = basis.polynomial_coefficients;
  if (auto s = build_frozen_factor(*t); !s) return s.error();
  t->q_bound = basis.training_q_bound;
  if (auto s = build_error_estimate(basis, *t); !s) return s.error();
  return ReducedModel(std::move(t));
}

Result<ReducedModel> with_solver_options(const ReducedModel& model, const ReducedSolverOptions& options) {
  if (auto s = check_options(options); !s) return s.error();
  auto t = std::make_shared<ReducedTables>(model.tables());
  t->options = options;
  t->lane_kernels = &detail::reduced_lane_kernels(options.kernel_isa);
  t->error_bound_m = options.error_bound_m;
  if (auto s = build_frozen_factor(*t); !s) return s.error();
  return ReducedModel(std::move(t));
}

Result<ReducedData> make_reduced_data(const ReducedModel& model) {
  const ReducedTables& t = model.tables();
  const auto r = static_cast<std::size_t>(t.r);
  const detail::ForceScratchSizes sizes = detail::force_scratch_sizes(t);
  ArenaPlan plan;
  const std::size_t monomial_count = t.polynomial.empty() ? 0 : r * (r + 1) / 2 + r * (r + 1) * (r + 2) / 6;
  plan.add<double>(9 * r)
      .add<double>(2 * r * r)
      .add<double>(sizes.displacements)
      .add<double>(sizes.rotations)
      .add<double>(sizes.tangent_rows);
  plan.add<double>(monomial_count);
  ReducedData data(Arena("reduced_data", plan.bytes()));
  std::span<double>* vectors[] = {&data.q,     &data.q_velocity, &data.q_start,  &data.v_start,   &data.v_iterate,
                                  &data.force, &data.external,   &data.residual, &data.correction};
  for (std::span<double>* vector : vectors) {
    auto carved = data.arena.allocate<double>("reduced vector", r);
    if (!carved.ok()) return carved.error();
    *vector = carved.value();
  }
  auto tangent = data.arena.allocate<double>("reduced tangent", r * r);
  auto factor = data.arena.allocate<double>("reduced factor", r * r);
  auto displacements = data.arena.allocate<double>("sample displacements", sizes.displacements);
  auto rotations = data.arena.allocate<double>("sample rotations", sizes.rotations);
  auto strains = data.arena.allocate<double>("sample tangent rows", sizes.tangent_rows);
  if (!tangent.ok()) return tangent.error();
  if (!factor.ok()) return factor.error();
  if (!displacements.ok()) return displacements.error();
  if (!rotations.ok()) return rotations.error();
  if (!strains.ok()) return strains.error();
  auto monomials = data.arena.allocate<double>("polynomial monomials", monomial_count);
  if (!monomials.ok()) return monomials.error();
  data.monomials = monomials.value();
  data.tangent = tangent.value();
  data.factor = factor.value();
  data.sample_displacements = displacements.value();
  data.sample_rotations = rotations.value();
  data.sample_tangent_rows = strains.value();
  std::fill(data.sample_rotations.begin(), data.sample_rotations.end(), 0.0);
  const std::size_t lanes = sizes.rotations / 9;  // identities, k-major over the lanes
  for (std::size_t d = 0; d < 3; ++d)
    std::fill_n(data.sample_rotations.begin() + static_cast<std::ptrdiff_t>(4 * d * lanes), lanes, 1.0);
  return data;
}

Result<ReducedDisplaySet> make_reduced_display_set(const ReducedModel& model, std::span<const std::int32_t> nodes) {
  constexpr std::size_t L = detail::kSampleLanes;
  const ReducedTables& t = model.tables();
  const auto r = static_cast<std::size_t>(t.r);
  ReducedDisplaySet display;
  display.nodes.assign(nodes.begin(), nodes.end());
  display.basis_size = t.r;
  const std::size_t values = 3 * nodes.size(), panels = (values + L - 1) / L;
  display.panels.assign(panels * r * L, 0.0);
  if (t.has_lift) display.lift_panels.assign(panels * 3 * L, 0.0);
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    if (nodes[k] < 0 || nodes[k] >= t.node_count)
      return field_error(
          "display node " + std::to_string(k) + " (" + std::to_string(nodes[k]) + ") is not a node of the model",
          "nodes");
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t v = 3 * k + c, row = 3 * static_cast<std::size_t>(nodes[k]) + c;
      for (std::size_t j = 0; j < r; ++j) display.panels[(v / L * r + j) * L + v % L] = t.rows[row * r + j];
      for (std::size_t j = 0; j < 3 && t.has_lift; ++j)
        display.lift_panels[(v / L * 3 + j) * L + v % L] = t.lift_rows[3 * row + j];
    }
  }
  return display;
}

std::int64_t ReducedModel::node_count() const { return tables_->node_count; }
int ReducedModel::basis_size() const { return tables_->r; }
const ReducedSolverOptions& ReducedModel::options() const { return tables_->options; }
ReducedForceKind ReducedModel::force_kind() const { return tables_->force_kind; }
int ReducedModel::sample_count() const { return tables_->sample_count; }

std::int64_t ReducedModel::memory_bytes() const {
  const ReducedTables& t = *tables_;
  std::size_t doubles = 0;
  for (const std::vector<double>* v : {&t.rows,
                                       &t.lift_rows,
                                       &t.gravity_r,
                                       &t.traction_r,
                                       &t.stiffness_r,
                                       &t.stiffness_lift_r,
                                       &t.spring_stiffness_r,
                                       &t.frozen_factor,
                                       &t.spring_rest_m,
                                       &t.sample_rows,
                                       &t.sample_lift,
                                       &t.sample_rest_m,
                                       &t.sample_gradients,
                                       &t.sample_root_stiffness,
                                       &t.sample_weight_volume,
                                       &t.sample_rest_tangent_r,
                                       &t.cubature_stiffness_r,
                                       &t.cubature_stiffness_lift_r,
                                       &t.polynomial,
                                       &t.q_bound,
                                       &t.missing_compliance})
    doubles += v->size();
  return static_cast<std::int64_t>(sizeof(ReducedTables) + 8 * doubles + 4 * t.spring_nodes.size() +
                                   sizeof(LameParameters) * t.sample_lame.size());
}

}  // namespace nav
