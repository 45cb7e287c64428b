// The reduced-coordinate Kalman filter: its build from a reduced basis and observed points,
// the Gauss-Markov time update, and the gated measurement update in Joseph form.
#include "nav/fusion/reduced_kalman.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

namespace nav {
namespace {

/// Sum of a[j] b[j] over n values, in index order.
double dot(const double* a, const double* b, int n) noexcept {
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += a[j] * b[j];
  return sum;
}

std::size_t at(int i) { return static_cast<std::size_t>(i); }

Status check_options(const ReducedKalmanOptions& o, int r) {
  if (o.correction_std.size() != at(r))
    return field_error("one standard deviation per reduced coordinate is needed (" + std::to_string(r) + ")",
                       "correction_std");
  for (std::size_t i = 0; i < o.correction_std.size(); ++i)
    if (!(std::isfinite(o.correction_std[i]) && o.correction_std[i] > 0.0))
      return field_error("must be a positive number", "correction_std[" + std::to_string(i) + "]");
  if (!(o.correlation_time_s > 0.0))
    return field_error("must be positive (infinity: a constant correction)", "correlation_time_s");
  if (!(std::isfinite(o.observation_std_m) && o.observation_std_m > 0.0))
    return field_error("must be a positive number of metres", "observation_std_m");
  if (!(std::isfinite(o.gate_chi_square) && o.gate_chi_square > 0.0))
    return field_error("must be a positive number", "gate_chi_square");
  return Done{};
}

Status check_point(const ObservedPoint& p, std::int32_t node_count, std::size_t k) {
  const std::string field = "points[" + std::to_string(k) + "]";
  double sum = 0.0;
  for (int a = 0; a < 4; ++a) {
    if (p.nodes[at(a)] < 0 || p.nodes[at(a)] >= node_count) return field_error("node out of range", field);
    if (!std::isfinite(p.weights[at(a)])) return field_error("weight is not finite", field);
    sum += p.weights[at(a)];
  }
  if (std::abs(sum - 1.0) > 1e-9) return field_error("the weights do not sum to 1", field);
  return Done{};
}

}  // namespace

std::vector<double> correction_std_from_training(const ReducedBasis& basis, double fraction) {
  std::vector<double> out(basis.training_q_bound.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = fraction * basis.training_q_bound[i];
  return out;
}

Result<ReducedKalmanModel> make_reduced_kalman_model(const TetMesh& mesh, const ReducedBasis& basis,
                                                     const ReducedModel& reduced, std::span<const ObservedPoint> points,
                                                     const ReducedKalmanOptions& options) {
  const std::size_t n3 = 3 * mesh.nodes_m.size();
  if (basis.mesh_fingerprint != mesh_fingerprint(mesh))
    return field_error("the basis belongs to another mesh", "mesh_fingerprint");
  if (basis.node_count != static_cast<std::int32_t>(mesh.nodes_m.size()) || reduced.node_count() != basis.node_count)
    return field_error("the node counts of mesh, basis and reduced model differ", "node_count");
  const int r = basis.basis_size;
  if (r < 1 || basis.basis.size() != n3 * at(r) || reduced.basis_size() != r)
    return field_error("the basis is not 3 node_count x basis_size, or not the reduced model's", "basis");
  if (!basis.diaphragm_lift.empty() && basis.diaphragm_lift.size() != 3 * n3)
    return field_error("the lift is not 3 node_count x 3", "diaphragm_lift");
  if (points.empty()) return field_error("at least one observed point is needed", "points");
  if (auto status = check_options(options, r); !status.ok()) return status.error();
  for (std::size_t k = 0; k < points.size(); ++k)
    if (auto status = check_point(points[k], basis.node_count, k); !status.ok()) return status.error();

  ReducedKalmanModel m;
  m.r = r;
  m.point_count = static_cast<int>(points.size());
  m.has_lift = !basis.diaphragm_lift.empty();
  m.decay = std::exp(-reduced.options().step_s / options.correlation_time_s);
  m.observation_variance_m2 = options.observation_std_m * options.observation_std_m;
  m.gate_chi_square = options.gate_chi_square;
  m.rest_m.assign(3 * points.size(), 0.0);
  m.rows.assign(3 * points.size() * at(r), 0.0);
  if (m.has_lift) m.lift_rows.assign(9 * points.size(), 0.0);
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int a = 0; a < 4; ++a) {
      const double w = points[k].weights[at(a)];
      const auto node = static_cast<std::size_t>(points[k].nodes[at(a)]);
      for (int c = 0; c < 3; ++c) {
        const std::size_t dof = 3 * node + at(c);
        m.rest_m[3 * k + at(c)] += w * mesh.nodes_m[node][at(c)];
        for (int j = 0; j < r; ++j) m.rows[(3 * k + at(c)) * at(r) + at(j)] += w * basis.basis[at(j) * n3 + dof];
        if (m.has_lift)
          for (int e = 0; e < 3; ++e) m.lift_rows[9 * k + at(3 * c + e)] += w * basis.diaphragm_lift[at(e) * n3 + dof];
      }
    }
  m.prior_variance.resize(at(r));
  m.step_variance.resize(at(r));
  for (int i = 0; i < r; ++i) {
    m.prior_variance[at(i)] = options.correction_std[at(i)] * options.correction_std[at(i)];
    m.step_variance[at(i)] = (1.0 - m.decay * m.decay) * m.prior_variance[at(i)];
  }
  return m;
}

Result<ReducedKalmanData> make_reduced_kalman_data(const ReducedKalmanModel& model) {
  const std::size_t r = at(model.r), points3 = 3 * at(model.point_count);
  ArenaPlan plan;
  plan.add<double>(r).add<double>(r * r).add<double>(r).add<double>(points3);
  plan.add<double>(3 * r).add<double>(3 * r).add<double>(r * r).add<double>(3 * r);
  ReducedKalmanData data(Arena("reduced Kalman filter", plan.bytes()));
  const auto carve = [&](std::string_view what, std::size_t count, std::span<double>& out) -> Status {
    auto span = data.arena.allocate<double>(what, count);
    if (!span.ok()) return span.error();
    out = span.value();
    return Done{};
  };
  for (auto [what, count, out] :
       {std::tuple{"correction", r, &data.correction}, std::tuple{"covariance", r * r, &data.covariance},
        std::tuple{"model_q", r, &data.model_q}, std::tuple{"model_points_m", points3, &data.model_points_m},
        std::tuple{"cross", 3 * r, &data.cross}, std::tuple{"gain", 3 * r, &data.gain},
        std::tuple{"joseph", r * r, &data.joseph}, std::tuple{"joseph_cross", 3 * r, &data.joseph_cross}})
    if (auto status = carve(what, count, *out); !status.ok()) return status.error();
  std::copy(model.rest_m.begin(), model.rest_m.end(), data.model_points_m.begin());
  reset(model, data);
  return data;
}

void reset(const ReducedKalmanModel& model, ReducedKalmanData& data) noexcept {
  const int r = model.r;
  std::fill(data.correction.begin(), data.correction.end(), 0.0);
  std::fill(data.covariance.begin(), data.covariance.end(), 0.0);
  for (int i = 0; i < r; ++i) data.covariance[at(i * r + i)] = model.prior_variance[at(i)];
}

void predict(const ReducedKalmanModel& model, ReducedKalmanData& data, const ReducedData& reduced) noexcept {
  const int r = model.r;
  const double a = model.decay;
  for (int i = 0; i < r; ++i) data.correction[at(i)] *= a;
  for (int i = 0; i < r; ++i) {
    for (int j = 0; j < r; ++j) data.covariance[at(i * r + j)] *= a * a;
    data.covariance[at(i * r + i)] += model.step_variance[at(i)];
  }
  if (reduced.q.size() != at(r)) {
    data.health.raise(HealthFlag::bad_sample);
    return;
  }
  bool finite = true;
  for (int i = 0; i < r; ++i) finite = finite && std::isfinite(reduced.q[at(i)]);
  for (double d : reduced.prescribed_m) finite = finite && std::isfinite(d);
  if (!finite) {
    data.health.raise(HealthFlag::non_finite_state);
    return;
  }
  std::copy(reduced.q.begin(), reduced.q.end(), data.model_q.begin());
  for (int row = 0; row < 3 * model.point_count; ++row) {
    double value = model.rest_m[at(row)] + dot(model.rows.data() + at(row) * at(r), data.model_q.data(), r);
    if (model.has_lift)
      for (int e = 0; e < 3; ++e) value += model.lift_rows[3 * at(row) + at(e)] * reduced.prescribed_m[e];
    data.model_points_m[at(row)] = value;
  }
}

bool update(const ReducedKalmanModel& model, ReducedKalmanData& data, int point, const Point3& observed_m,
            TimeNs time_ns) noexcept {
  const int r = model.r;
  const bool finite = std::isfinite(observed_m[0]) && std::isfinite(observed_m[1]) && std::isfinite(observed_m[2]);
  if (point < 0 || point >= model.point_count || !finite || time_ns < data.last_update_ns) {
    data.health.raise(HealthFlag::bad_sample);
    ++data.rejected_updates;
    return false;
  }
  const double* h = model.rows.data() + 3 * at(point) * at(r);  // H: 3 x r
  // G = P H^T (r x 3), S = H G + R, innovation y = z - (model point + H dq).
  for (int i = 0; i < r; ++i)
    for (int c = 0; c < 3; ++c) data.cross[at(3 * i + c)] = dot(data.covariance.data() + at(i * r), h + at(c * r), r);
  Eigen::Matrix3d s;
  for (int c = 0; c < 3; ++c)
    for (int e = 0; e < 3; ++e) {
      double sum = 0.0;
      for (int j = 0; j < r; ++j) sum += h[at(c * r + j)] * data.cross[at(3 * j + e)];
      s(c, e) = sum;
    }
  s = 0.5 * (s + s.transpose().eval());
  s.diagonal().array() += model.observation_variance_m2;
  Eigen::Vector3d y;
  for (int c = 0; c < 3; ++c)
    y[c] =
        observed_m[at(c)] - data.model_points_m[3 * at(point) + at(c)] - dot(h + at(c * r), data.correction.data(), r);
  const Eigen::LLT<Eigen::Matrix3d> factor(s);
  if (factor.info() != Eigen::Success) {
    data.health.raise(HealthFlag::non_finite_state);
    ++data.rejected_updates;
    return false;
  }
  const Eigen::Matrix3d s_inverse = factor.solve(Eigen::Matrix3d::Identity());
  data.last_mahalanobis_squared = y.dot(s_inverse * y);
  if (!(data.last_mahalanobis_squared <= model.gate_chi_square)) {
    data.health.raise(HealthFlag::bad_sample);
    ++data.rejected_updates;
    return false;
  }
  // K = G S^-1; dq += K y.
  for (int i = 0; i < r; ++i)
    for (int e = 0; e < 3; ++e) {
      double sum = 0.0;
      for (int c = 0; c < 3; ++c) sum += data.cross[at(3 * i + c)] * s_inverse(c, e);
      data.gain[at(3 * i + e)] = sum;
    }
  for (int i = 0; i < r; ++i) {
    double sum = 0.0;
    for (int c = 0; c < 3; ++c) sum += data.gain[at(3 * i + c)] * y[c];
    data.correction[at(i)] += sum;
  }
  // Joseph form through its rank-3 structure: M = (I - K H) P = P - K G^T,
  // P' = M (I - K H)^T + K R K^T = M - (M H^T) K^T + R K K^T, then symmetrised.
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < r; ++j) {
      double kg = 0.0;
      for (int c = 0; c < 3; ++c) kg += data.gain[at(3 * i + c)] * data.cross[at(3 * j + c)];
      data.joseph[at(i * r + j)] = data.covariance[at(i * r + j)] - kg;
    }
  for (int i = 0; i < r; ++i)
    for (int c = 0; c < 3; ++c)
      data.joseph_cross[at(3 * i + c)] = dot(data.joseph.data() + at(i * r), h + at(c * r), r);
  for (int i = 0; i < r; ++i)
    for (int j = i; j < r; ++j) {
      double mk_ij = 0.0, mk_ji = 0.0, kk = 0.0;
      for (int c = 0; c < 3; ++c) {
        mk_ij += data.joseph_cross[at(3 * i + c)] * data.gain[at(3 * j + c)];
        mk_ji += data.joseph_cross[at(3 * j + c)] * data.gain[at(3 * i + c)];
        kk += data.gain[at(3 * i + c)] * data.gain[at(3 * j + c)];
      }
      const double noise = model.observation_variance_m2 * kk;
      const double mean =
          0.5 * ((data.joseph[at(i * r + j)] - mk_ij + noise) + (data.joseph[at(j * r + i)] - mk_ji + noise));
      data.covariance[at(i * r + j)] = mean;
      data.covariance[at(j * r + i)] = mean;
    }
  data.last_update_ns = time_ns;
  ++data.accepted_updates;
  return true;
}

PointEstimate estimate_point(const ReducedKalmanModel& model, const ReducedKalmanData& data, int point) noexcept {
  PointEstimate out;
  if (point < 0 || point >= model.point_count) return out;
  const int r = model.r;
  const double* h = model.rows.data() + 3 * at(point) * at(r);
  for (int c = 0; c < 3; ++c)
    out.position_m[at(c)] = data.model_points_m[3 * at(point) + at(c)] + dot(h + at(c * r), data.correction.data(), r);
  // H P H^T: row i of P H^T once, then its share of every entry.
  std::array<double, 9> sum{};
  for (int i = 0; i < r; ++i) {
    const double* p_row = data.covariance.data() + at(i * r);
    const double ph[3] = {dot(p_row, h, r), dot(p_row, h + at(r), r), dot(p_row, h + at(2 * r), r)};
    for (int c = 0; c < 3; ++c)
      for (int e = 0; e < 3; ++e) sum[at(3 * c + e)] += h[at(c * r + i)] * ph[e];
  }
  for (int c = 0; c < 3; ++c)
    for (int e = 0; e < 3; ++e) out.covariance_m2[at(3 * c + e)] = 0.5 * (sum[at(3 * c + e)] + sum[at(3 * e + c)]);
  return out;
}

void corrected_coordinates(const ReducedKalmanModel& model, const ReducedKalmanData& data,
                           std::span<double> out_q) noexcept {
  const std::size_t count = std::min(out_q.size(), at(model.r));
  for (std::size_t i = 0; i < count; ++i) out_q[i] = data.model_q[i] + data.correction[i];
}

}  // namespace nav
