#pragma once
// The needle-tissue interaction coupled to a tissue model, whichever it is: the full-order
// tetrahedral tissue (tissue_coupling.hpp) or the reduced-order one (reduced_coupling.hpp).
// The constraint forces go to the tissue as point forces, the tissue's displacements come
// back to the interaction, and the interaction predicts the tissue's response to force
// changes through the compliance it was given. Multi-rate: the needle and its constraint
// forces step at every tick (1 kHz) with the last compliance, the tissue once every
// needle_steps_per_tissue_step ticks with the forces of that tick.
#include <cstdint>
#include <span>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/needle/needle_tissue_model.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// The immutable coupled scene: the needle-tissue model attached to the tissue's nodes.
template <class TissueModel>
struct CoupledNeedleModelOf {
  NeedleTissueModel interaction;
  const TissueModel* tissue = nullptr;  ///< not owned; outlives this model
  int needle_steps_per_tissue_step = 1;
  std::size_t max_point_forces = 16;  ///< the needle's share of the tissue scene's max_point_forces
  /// Room for the tissue's other point forces (an attached ligament's), which step_tissue()
  /// joins after the needle's: the two together within the tissue scene's max_point_forces.
  std::size_t other_point_forces = 0;
};

/// State of the coupled scene: the interaction's data, the tissue's data, the tissue
/// displacements the interaction sees, and the point forces handed to the tissue.
template <class TissueData>
struct CoupledNeedleDataOf {
  Arena arena;
  NeedleTissueData interaction;
  TissueData tissue;
  /// The tissue stepped once more from its state under the forces it carries: where it will be
  /// at the end of its next step if the forces do not change (its free motion).
  TissueData free_tissue;
  /// 3 per tissue node: the free motion's, which the interaction meets (plus the compliance's
  /// response to the forces' changes since the last tissue step).
  std::span<double> displacements_m;
  std::span<PointForce> point_forces;
  /// Nodes whose displacements a tissue step refreshes and their new values (used when the
  /// tissue rebuilds displacements on demand, as the reduced one does; empty otherwise).
  std::span<std::int32_t> refreshed_nodes;
  std::span<double> refreshed_displacements_m;
  std::int64_t refresh_cursor = 0;  ///< next node of the round-robin refresh
  std::int64_t ticks = 0;
  std::size_t point_force_count = 0;  ///< the first point_force_count point_forces went to the last tissue step
  int dropped_point_forces = 0;       ///< forces beyond max_point_forces at the last tissue step
  CoupledNeedleDataOf(Arena block, NeedleTissueData interaction_data, TissueData tissue_data,
                      TissueData free_tissue_data)
      : arena(std::move(block)),
        interaction(std::move(interaction_data)),
        tissue(std::move(tissue_data)),
        free_tissue(std::move(free_tissue_data)) {}
};

/// One needle tick; the tissue steps on every needle_steps_per_tissue_step-th tick. More
/// distinct loaded nodes than max_point_forces: the smallest forces are dropped and pool_full raised.
/// It is step_needle(), then step_tissue() without other loads when the tissue is due.
template <class TissueModel, class TissueData>
void step(const CoupledNeedleModelOf<TissueModel>& model, CoupledNeedleDataOf<TissueData>& data,
          const NeedleInputs& inputs) noexcept;

/// The needle's part of a tick: the interaction steps against the tissue displacements of the
/// last tissue step. For a caller that schedules the tissue itself (the operating loop); it and
/// step_tissue() leave `ticks` alone and are defined in coupled_needle_step.hpp (include it).
template <class TissueModel, class TissueData>
void step_needle(const CoupledNeedleModelOf<TissueModel>& model, CoupledNeedleDataOf<TissueData>& data,
                 const NeedleInputs& inputs) noexcept;

/// The tissue's part: the needle's point forces of its last step (capped as in step()) join
/// `tissue_inputs`, the tissue's other loads (a diaphragm's prescribed displacement; its
/// point_forces, at most model.other_point_forces, are kept after the needle's), the tissue
/// steps, and steps once more on free_tissue under the same inputs: the interaction meets that
/// free motion. (The constraints then see where the tissue will be at its next step, as
/// constraint-based coupling does; meeting it where it was lets a needle on an inertial tissue
/// stepped at the needle's rate run away.)
template <class TissueModel, class TissueData>
void step_tissue(const CoupledNeedleModelOf<TissueModel>& model, CoupledNeedleDataOf<TissueData>& data,
                 TissueInputs tissue_inputs) noexcept;

/// Carries a free needle (every layer outside, no path point held) straight and at rest to
/// `base`, as make_needle_tissue_data() builds it: a tool (re)acquired by its tracker away from
/// where the model left it. Returns false, changing nothing, when the needle holds tissue or
/// `base` is not finite with a unit quaternion.
bool place_free_needle(const NeedleTissueModel& model, NeedleTissueData& data, const NeedlePose& base) noexcept;

}  // namespace nav
