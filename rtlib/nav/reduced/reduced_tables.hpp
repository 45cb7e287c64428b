#pragma once
// The precomputed tables of a ReducedModel, shared by its build and step. Internal to
// rtlib/nav/reduced. Matrices are row-major; the basis rows of a node are contiguous.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nav/reduced/reduced_basis.hpp"
#include "nav/reduced/reduced_lane_kernels.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/tissue/elastic_material.hpp"

namespace nav::detail {

/// Per-model tables of a ReducedModel.
struct ReducedTables {
  ReducedSolverOptions options;
  ReducedForceKind force_kind = ReducedForceKind::linear;
  int r = 0;  ///< basis size
  std::int64_t node_count = 0;
  bool has_lift = false;
  std::size_t max_point_forces = 0;
  double gain_pa = 0.0;                              ///< St Venant-Kirchhoff incompressibility gain
  const ReducedLaneKernels* lane_kernels = nullptr;  ///< the variant of options.kernel_isa

  std::vector<double> rows;                ///< (3 node_count) x r: the basis U
  std::vector<double> lift_rows;           ///< (3 node_count) x 3: the lift L (empty without one)
  std::vector<double> gravity_r;           ///< r: U^T M g
  std::vector<double> traction_r;          ///< 3 x r: U^T (area share) per traction axis
  std::vector<double> stiffness_r;         ///< r x r: U^T K U (elastic, rest)
  std::vector<double> stiffness_lift_r;    ///< r x 3: U^T K L
  std::vector<double> spring_stiffness_r;  ///< r x r: k sum U_s^T U_s over spring nodes
  std::vector<double> frozen_factor;       ///< r x r: lower Cholesky factor of the frozen system
  std::vector<std::int32_t> spring_nodes;  ///< free spring nodes
  std::vector<double> spring_rest_m;       ///< 3 per spring node
  double spring_stiffness_n_m = 0.0;

  // The sampled tetrahedra of a cubature, blocked by kSampleLanes (structure of arrays):
  // value x of sample s = kSampleLanes b + l is at [(b X + x) kSampleLanes + l], X values per
  // sample. The lanes past sample_count are padding: zero rows, gradients and weights (they
  // deform by nothing and add nothing).
  int sample_count = 0;                       ///< m
  int sample_blocks = 0;                      ///< ceil(m / kSampleLanes)
  std::vector<double> sample_rows;            ///< 12 r per sample: row i = 3a + c, column j at x = r i + j
  std::vector<double> sample_lift;            ///< 12 x 3 per sample (empty without a lift)
  std::vector<double> sample_rest_m;          ///< 12 per sample
  std::vector<double> sample_gradients;       ///< 12 per sample: 3a + k = component k of vertex a's gradient
  std::vector<double> sample_root_stiffness;  ///< 6 x 12 per sample: G = sqrt(w V) D^1/2 B, G^T G = w K_e
  std::vector<double> sample_weight_volume;   ///< 1 per sample: w V0
  std::vector<LameParameters> sample_lame;    ///< one per sample, padded with zeros (not blocked)
  std::vector<double> sample_rest_tangent_r;  ///< r x r: K_S = sum over samples of w U_s^T K_s U_s (symmetric)
  /// r x r: K_r - K_S, the linear stiffness the samples' full forces are completed with.
  std::vector<double> cubature_stiffness_r;
  std::vector<double> cubature_stiffness_lift_r;  ///< r x 3: U^T K L - sum w U_s^T K_s L_s

  std::vector<double> polynomial;  ///< stvk_cubic_polynomial only: see stvk_polynomial.hpp
  std::vector<double> q_bound;     ///< r, or empty: no envelope

  // The error estimate (empty without a calibration): gain x the sum over loaded nodes of
  // |M_n f_n| (ReducedErrorCalibration).
  std::vector<double> missing_compliance;  ///< 6 per node: M_n
  double error_gain = 0.0;
  double error_bound_m = 0.0;  ///< the flag's threshold (options.error_bound_m)
};

/// The system matrix a I + b K + c Ks of a Newton iteration (Rayleigh damping acts on the
/// elastic stiffness K, not on the frame springs Ks):
/// implicit Euler (1 + h alpha) I + (h^2 + h beta) K + h^2 Ks;
/// quasi-static (alpha / h) I + (1 + beta / h) K + Ks.
struct SystemCoefficients {
  double identity = 0.0, stiffness = 0.0, spring = 0.0;
};

inline SystemCoefficients system_coefficients(const ReducedSolverOptions& o) {
  const double h = o.step_s;
  if (o.integrator == ReducedIntegrator::implicit_euler)
    return {1.0 + h * o.rayleigh_mass_per_s, h * h + h * o.rayleigh_stiffness_s, h * h};
  return {o.rayleigh_mass_per_s / h, 1.0 + o.rayleigh_stiffness_s / h, 1.0};
}

}  // namespace nav::detail
