#pragma once
// Linear tetrahedral FEM tissue (corotational, or linear for small displacements) with
// lumped mass, Rayleigh damping, implicit Euler, quasi-static and explicit central
// difference steps: the workhorse of the tissue ladder. Model/Data: the model is built once
// and immutable; the data is one arena; step() is noexcept, allocation-free, fixed-cost
// and bitwise repeatable.
#include <cstdint>
#include <memory>
#include <span>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

namespace detail {
struct TetFemTables;
}

/// The immutable part of a tetrahedral FEM tissue: element tensors, masses, supports and
/// the factorisation of the rest system. Cheap to move, shares its tables when copied.
class TetFemModel {
 public:
  std::int64_t node_count() const;
  std::int64_t tet_count() const;
  /// Degrees of freedom left after fixed and prescribed nodes.
  std::int64_t free_dof_count() const;
  const TissueSolverOptions& options() const;
  /// 2 / omega_max of the lumped-mass rest system (power iteration at init), reduced under
  /// the incompressibility penalty for element volume changes up to 10 %: the estimate of the
  /// largest stable explicit step, in seconds.
  double stable_step_s() const;
  /// Entries of the LDL^T factor below the diagonal (0 without one).
  std::int64_t factor_nonzeros() const;
  /// Bytes the LDL^T factor holds (0 without one).
  std::int64_t factor_bytes() const;
  /// Node rest positions, 3 per node, in metres.
  std::span<const double> rest_positions_m() const;
  /// Lumped nodal masses in kilograms.
  std::span<const double> nodal_masses_kg() const;

  const detail::TetFemTables& tables() const { return *tables_; }
  explicit TetFemModel(std::shared_ptr<const detail::TetFemTables> tables) : tables_(std::move(tables)) {}

 private:
  std::shared_ptr<const detail::TetFemTables> tables_;
};

/// The state and workspace of one TetFemModel, carved from one arena at init.
struct TetFemData {
  Arena arena;
  std::span<double> positions_m;     ///< 3 per node
  std::span<double> velocities_m_s;  ///< 3 per node
  HealthFlags health;                ///< raised by steps, cleared by the caller
  TissueStepReport report;           ///< what the last step did
  std::int64_t steps = 0;            ///< steps taken (refused steps not counted)

  // Workspace (meaningless between steps).
  std::span<double> forces_n, rhs, solution, residual, preconditioned, direction, product;
  std::span<double> backup_positions_m, backup_velocities_m_s, free_work;
  std::span<double> element_rotations;  ///< 9 per element (column-major 3x3), last good one
  std::span<double> node_rotations;     ///< 9 per node, for warping
  std::span<double> tangent_stresses;   ///< 9 per element, St Venant-Kirchhoff only (else empty)

  explicit TetFemData(Arena block) : arena(std::move(block)) {}
};

/// Builds the model. Errors name the parameter or region at fault: a material out of range,
/// an element inverted or flat, a node index out of range, a quasi-static or implicit
/// system left singular, a step that is not positive.
Result<TetFemModel> make_tet_fem_model(const TetMesh& mesh, const TissueScene& scene,
                                       const TissueSolverOptions& options);

/// The data of `model`, at rest with zero velocity.
Result<TetFemData> make_tet_fem_data(const TetFemModel& model);

/// Advances the tissue by one step of model.options().step_s under `inputs`.
void step(const TetFemModel& model, TetFemData& data, const TissueInputs& inputs) noexcept;

/// Copies the state a step starts from (positions, velocities, the element rotations kept for
/// inverted elements, the step count and report) of `from` into `to`, data of the same model;
/// clears `to`'s health flags. Allocation-free.
void copy_state(const TetFemData& from, TetFemData& to) noexcept;

/// Whether rest_step_response_m() can answer: the model keeps its rest factor (ldlt_warped)
/// and steps implicitly (implicit Euler or quasi-static).
bool has_rest_step_response(const TetFemModel& model) noexcept;

/// The displacement of every node's point (point_displacements_m(); 3 per node) over one
/// step per newton of a point force on node `node` along axis `axis`, from the rest system's
/// LDL^T factor without the rotations of a corotational step: h^2 A^-1 P e for implicit Euler,
/// A^-1 P e quasi-static (A the rest system, P the force's spread over its patch), seen through
/// the patches. Exact for linear elements from rest. `work` holds 2 free_dof_count() doubles.
/// Returns false, `out_m` zeroed, when the model has no such response or the force reaches no
/// free node. Allocation-free.
bool rest_step_response_m(const TetFemModel& model, std::int32_t node, int axis, std::span<double> out_m,
                          std::span<double> work) noexcept;

/// The displacement from rest of the point a point force on each node acts on (3 per node):
/// the node's own, or the weighted mean over its patch (TissueScene::point_force_own_share).
/// `out_m` holds 3 per node. Allocation-free.
void point_displacements_m(const TetFemModel& model, const TetFemData& data, std::span<double> out_m) noexcept;

/// Elastic energy of the current positions, in joules (element rotations recomputed).
double elastic_energy_j(const TetFemModel& model, const TetFemData& data) noexcept;

/// Kinetic energy 1/2 v^T M v, in joules.
double kinetic_energy_j(const TetFemModel& model, const TetFemData& data) noexcept;

/// Potential of gravity -sum m g.x, in joules (zero at the origin).
double gravity_energy_j(const TetFemModel& model, const TetFemData& data) noexcept;

}  // namespace nav
