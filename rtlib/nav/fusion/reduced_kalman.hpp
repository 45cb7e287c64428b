#pragma once
// A Kalman filter on the reduced coordinates of a reduced liver: it assimilates observed
// positions of mesh points (the tumour seen in ultrasound, optionally boundary points) into
// the reduced state, and gives each observed point's position with its 3x3 covariance.
//
// Formulation (exact, linear-Gaussian): the reduced model's own step is the process model of
// the mean; the filter estimates the model's error as a correction dq of the reduced
// coordinates, so that the tissue's displacement is u = U (q_model + dq) + L d. The correction
// is a first-order Gauss-Markov process dq' = a dq + w per model step, a = exp(-h / tau),
// w ~ N(0, (1 - a^2) S), S = diag(correction_std^2) its stationary covariance (also the prior):
// the model's error is bounded (a fraction of the training envelope) and slowly varying, so
// the covariance stays bounded in the directions the observations never see; tau = infinity is
// a constant correction (no process noise). An observed point p = x0 + H (q_model + dq) + L_p d
// is linear in dq, so the update is an exact Kalman update, with the covariance in Joseph form
// (I - K H) P (I - K H)^T + K R K^T evaluated through its rank-3 structure in O(r^2) and then
// symmetrised. The correction is kept beside the model (not written into q): the model's
// quasi-static or implicit step would otherwise pull a fed-back correction back towards its own
// equilibrium at every step, whereas the errors it corrects (stiffness, unmodelled loads) persist.
// Model/Data: built at init, one arena; predict/update are noexcept, allocation-free,
// fixed-cost and bitwise repeatable.
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "nav/core/arena.hpp"
#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/reduced/reduced_basis.hpp"
#include "nav/reduced/reduced_model.hpp"

namespace nav {

/// A material point of the mesh: sum of weights[a] times node nodes[a] (barycentric weights in
/// a tetrahedron, or one node with weight 1 and the rest 0). The weights sum to 1.
struct ObservedPoint {
  std::array<std::int32_t, 4> nodes{0, 0, 0, 0};
  std::array<double, 4> weights{1.0, 0.0, 0.0, 0.0};
};

/// The observed point that is the mesh node `node`.
constexpr ObservedPoint observed_node(std::int32_t node) { return {{node, node, node, node}, {1.0, 0.0, 0.0, 0.0}}; }

/// Noise and gating settings of the filter.
struct ReducedKalmanOptions {
  /// Per reduced coordinate (r values, units of q): the prior and stationary standard
  /// deviation of the correction (see correction_std_from_training).
  std::vector<double> correction_std;
  /// Correlation time of the correction in seconds (positive; infinity: a constant correction).
  double correlation_time_s = std::numeric_limits<double>::infinity();
  double observation_std_m = 0.001;  ///< per axis, of an observed point's position
  /// Observations whose squared Mahalanobis distance to the prediction exceeds this are
  /// rejected (chi-square with 3 degrees of freedom: 16.27 is a false rejection rate of 1e-3).
  double gate_chi_square = 16.27;
};

/// correction_std_i = fraction * basis.training_q_bound[i] (empty when the basis has no envelope).
std::vector<double> correction_std_from_training(const ReducedBasis& basis, double fraction);

/// The immutable part of the filter: observation rows and noise settings of one reduced model.
struct ReducedKalmanModel {
  int r = 0;            ///< reduced coordinates
  int point_count = 0;  ///< observed points
  bool has_lift = false;
  double decay = 1.0;  ///< a = exp(-h / tau) per model step
  double observation_variance_m2 = 0.0;
  double gate_chi_square = 0.0;
  std::vector<double> rest_m;          ///< 3 per point: x0
  std::vector<double> rows;            ///< per point, 3 x r row-major: H
  std::vector<double> lift_rows;       ///< per point, 3 x 3 row-major: L_p (empty without a lift)
  std::vector<double> prior_variance;  ///< r: S = correction_std^2
  std::vector<double> step_variance;   ///< r: (1 - a^2) S, added at every predict
};

/// The filter's state and workspace, carved from one arena at init.
struct ReducedKalmanData {
  Arena arena;
  std::span<double> correction;      ///< dq (r)
  std::span<double> covariance;      ///< P of dq (r x r, row-major, symmetric)
  std::span<double> model_q;         ///< the reduced model's q at the last predict (r)
  std::span<double> model_points_m;  ///< 3 per point: x0 + H q_model + L_p d at the last predict
  HealthFlags health;                ///< raised by predict/update, cleared by the caller
  TimeNs last_update_ns = std::numeric_limits<TimeNs>::min();  ///< of the last accepted observation
  std::int64_t accepted_updates = 0, rejected_updates = 0;
  double last_mahalanobis_squared = 0.0;  ///< of the last finite observation, accepted or not

  // Workspace (meaningless between calls).
  std::span<double> cross;         ///< P H^T (r x 3)
  std::span<double> gain;          ///< K (r x 3)
  std::span<double> joseph;        ///< (I - K H) P, then its product with (I - K H)^T (r x r)
  std::span<double> joseph_cross;  ///< (I - K H) P H^T (r x 3)

  explicit ReducedKalmanData(Arena block) : arena(std::move(block)) {}
};

/// Builds the filter of `reduced` (a model of `basis` on `mesh`) observing `points`. Errors
/// name the field at fault (basis, points[k], correction_std, ...).
Result<ReducedKalmanModel> make_reduced_kalman_model(const TetMesh& mesh, const ReducedBasis& basis,
                                                     const ReducedModel& reduced, std::span<const ObservedPoint> points,
                                                     const ReducedKalmanOptions& options);

/// The filter's data at its prior: dq = 0, P = S, model points at rest.
Result<ReducedKalmanData> make_reduced_kalman_data(const ReducedKalmanModel& model);

/// Back to the prior (dq = 0, P = S), keeping the model points and the counters.
void reset(const ReducedKalmanModel& model, ReducedKalmanData& data) noexcept;

/// The time update after one step of the reduced model: dq = a dq, P = a^2 P + (1 - a^2) S,
/// and the model's own point positions from `reduced` (q and the diaphragm displacement). A
/// non-finite reduced state raises non_finite_state and keeps the previous model points.
void predict(const ReducedKalmanModel& model, ReducedKalmanData& data, const ReducedData& reduced) noexcept;

/// The measurement update with the observed position of point `point` (metres, the mesh's
/// frame) taken at `time_ns`. Rejected with bad_sample, the state untouched, when the point
/// index is out of range, the position is not finite, the time is before the last accepted
/// observation, or the squared Mahalanobis distance exceeds the gate. True when accepted.
bool update(const ReducedKalmanModel& model, ReducedKalmanData& data, int point, const Point3& observed_m,
            TimeNs time_ns) noexcept;

/// An observed point's estimated position and the 3x3 covariance of that estimate.
struct PointEstimate {
  Point3 position_m{};
  std::array<double, 9> covariance_m2{};  ///< row-major, H P H^T
};

/// The estimate of point `point` (zeros when the index is out of range).
PointEstimate estimate_point(const ReducedKalmanModel& model, const ReducedKalmanData& data, int point) noexcept;

/// The corrected reduced coordinates q_model + dq (r values), e.g. to reconstruct a surface.
void corrected_coordinates(const ReducedKalmanModel& model, const ReducedKalmanData& data,
                           std::span<double> out_q) noexcept;

/// The filter carried to another basis of the same liver (a rung of an escalation ladder):
/// dq' = A dq and P' = A P A^T + added, with A (to.r x from.r, row-major) the map between the
/// two coordinate sets and `added` (to.r x to.r, row-major; empty for none) the covariance of
/// directions the source basis lacks. The accepted and rejected counts and the last update time
/// go along; the model points are left to the next predict. `workspace` holds to.r x from.r values.
void carry_filter(const ReducedKalmanModel& from_model, const ReducedKalmanData& from,
                  const ReducedKalmanModel& to_model, ReducedKalmanData& to, std::span<const double> a,
                  std::span<const double> added, std::span<double> workspace) noexcept;

/// The prior covariance of the directions of `big` that a smaller basis lacks, with
/// T = U_big^T M U_small (big.r x r_small, row-major) the map from the smaller one:
/// N S N^T with N = I - T T^T and S the big filter's prior (init time).
std::vector<double> unseen_directions_prior(const ReducedKalmanModel& big, std::span<const double> transfer,
                                            int r_small);

}  // namespace nav
