#pragma once
// The offline calibration of a reduced model's online error estimate (ReducedErrorCalibration,
// evaluated by every reduced step): the static compliance the basis misses about every node
// (the full order's response to a unit force spread over the patch radius, 3 forward solves
// per free node with its rest factor, less the basis's own), then, on held-out loads solved by the full
// order, each load's reduced static solution, its true largest nodal error and the
// displacement the basis misses under its point forces. The gain
// is the geometric mean of true error over that displacement on the loads with point forces
// (the estimate is right on average in ratio); the report gives every load's figures, their
// correlation and the range of true over estimated error. Loads without point forces (gravity,
// the diaphragm) are the training envelope's to judge. Offline code: it allocates and returns
// errors naming the load.
#include <span>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/reduced/reduced_basis.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// The patch of the missing compliance, and how the held-out loads are solved by the reduced
/// model: Newton steps without relaxation (a relaxed step of a soft basis creeps towards its
/// equilibrium over thousands of steps).
struct ErrorCalibrationOptions {
  double patch_radius_m = 0.012;  ///< a probe's patch (TrainingLoadOptions::probe_patch_radius_m)
  /// Threads sharing the nodes' missing compliances (1: all on the caller's); the values do
  /// not depend on it.
  int threads = 1;
  ReducedStaticOptions reduced_static = [] {
    ReducedStaticOptions o;
    o.relaxation_per_s = 0.0;
    return o;
  }();
};

/// One held-out load's figures.
struct HeldOutEstimate {
  std::string load;
  double true_error_m = 0.0;       ///< largest nodal error of the reduced static solution
  double missed_m = 0.0;           ///< sum over loaded nodes of |M_n f_n| (0 without point forces)
  double estimated_error_m = 0.0;  ///< gain x missed_m
};

/// What the calibration met, load by load, in the order given, and the loads the reduced
/// model did not bring to equilibrium (left out, with the reason).
struct ErrorCalibrationReport {
  std::vector<HeldOutEstimate> loads;
  std::vector<Error> unsolved;
};

/// Pearson's correlation of two equally long series (0 when either is constant).
double pearson_correlation(std::span<const double> a, std::span<const double> b);

/// Calibrates `basis`'s error estimate (its error_calibration is replaced) on `loads`, whose
/// full-order static displacements from rest are `full_order_m` (3 n values per load, in
/// order), on `scene` (the one the basis was trained on). Errors: sizes that differ, a
/// singular full-order system, fewer than 3 solved loads with point forces and a positive
/// error.
Result<ErrorCalibrationReport> calibrate_error_estimate(const TetMesh& mesh, const TissueScene& scene,
                                                        std::span<const TrainingLoad> loads,
                                                        std::span<const std::vector<double>> full_order_m,
                                                        ReducedBasis& basis,
                                                        const ErrorCalibrationOptions& options = {});

}  // namespace nav
