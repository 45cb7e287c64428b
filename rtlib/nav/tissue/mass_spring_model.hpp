#pragma once
// The cheapest rung of the tissue ladder: a mass-spring network on the edges of the
// tetrahedra with Promayon's direct volume constraint (digest 000, §2.4): after each explicit
// central-difference step the surface nodes are moved along the volume gradient so that the
// volume enclosed by the boundary returns exactly to its rest value. Model/Data: the model is
// immutable after init; step() is noexcept, allocation-free, fixed-cost and repeatable.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {

/// Settings of a mass-spring tissue.
struct MassSpringOptions {
  double step_s = 1e-4;              ///< explicit step; above stable_step_s() raises a flag
  double damping_per_s = 0.0;        ///< mass-proportional damping
  bool keep_volume = true;           ///< Promayon's constraint on the boundary's volume
  int volume_newton_iterations = 8;  ///< fixed count for the cubic in the multiplier
};

/// The precomputed tables of a MassSpringModel.
struct MassSpringTables {
  MassSpringOptions options;
  TetFemModel supports;  ///< masses, supports and loads of the scene (its elements unused)
  std::vector<std::array<std::int32_t, 2>> springs;
  std::vector<double> rest_length_m, stiffness_n_m;
  std::vector<std::array<std::int32_t, 3>> boundary_triangles;  ///< outward, mesh node indices
  std::vector<double> constraint_mask;                          ///< 1 per node: 1 on free boundary nodes, else 0
  double stable_step_s = 0.0;
  double rest_volume_m3 = 0.0;
};

/// Springs, masses, supports and boundary of a mass-spring tissue. Cheap to copy (shares
/// its tables).
class MassSpringModel {
 public:
  std::int64_t node_count() const { return tables_->supports.node_count(); }
  std::int64_t spring_count() const { return static_cast<std::int64_t>(tables_->springs.size()); }
  const MassSpringOptions& options() const { return tables_->options; }
  /// 2 / omega_max from a Gershgorin bound on M^-1 K, in seconds.
  double stable_step_s() const { return tables_->stable_step_s; }
  /// Volume enclosed by the boundary at rest, in m^3.
  double rest_volume_m3() const { return tables_->rest_volume_m3; }
  const MassSpringTables& tables() const { return *tables_; }

  explicit MassSpringModel(std::shared_ptr<const MassSpringTables> tables) : tables_(std::move(tables)) {}

 private:
  std::shared_ptr<const MassSpringTables> tables_;
};

/// State and workspace of a MassSpringModel, in one arena.
struct MassSpringData {
  Arena arena;
  std::span<double> positions_m, velocities_m_s;  ///< 3 per node
  HealthFlags health;
  TissueStepReport report;
  double volume_change_pct = 0.0;  ///< of the boundary's volume after the last step
  std::int64_t steps = 0;
  std::span<double> forces_n, volume_gradient, backup_positions_m, backup_velocities_m_s;  // workspace

  explicit MassSpringData(Arena block) : arena(std::move(block)) {}
};

/// Springs on every element edge, of stiffness sum over the incident elements of
/// E V / L^2 (Young's modulus spread over the edge's share of volume; Poisson's ratio has no
/// counterpart in a spring network, the volume constraint stands in for it). Errors as
/// make_tet_fem_model, and a step that is not positive.
Result<MassSpringModel> make_mass_spring_model(const TetMesh& mesh, const TissueScene& scene,
                                               const MassSpringOptions& options);

Result<MassSpringData> make_mass_spring_data(const MassSpringModel& model);

/// One explicit step, then the volume projection. Bad inputs are refused with the state
/// untouched (bad_sample); a non-finite result is rolled back (non_finite_state); a step
/// above the stable step raises unstable_step; tetrahedra of the mesh turned inside out are
/// counted in data.report and raise inverted_element.
void step(const MassSpringModel& model, MassSpringData& data, const TissueInputs& inputs) noexcept;

/// Volume enclosed by `triangles` (outward) at positions x: sum of x_a . (x_b x x_c) / 6.
double enclosed_volume_m3(std::span<const std::array<std::int32_t, 3>> triangles, std::span<const double> x) noexcept;

}  // namespace nav
