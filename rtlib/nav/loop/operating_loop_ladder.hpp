#pragma once
// The liver step of an operating loop's tissue tick, with its ladder's moves: internal to
// rtlib/nav/loop (used by operating_loop_tick.cpp).
#include "nav/loop/operating_loop.hpp"

namespace nav::detail {

/// Steps the active rung's liver under `inputs` (with the needle's forces when the loop has a
/// needle). On a ladder, when the rung's indicator fires (out of its envelope, or a step undone
/// as non-finite) for escalate_after_steps steps and escalation is allowed, the liver's state
/// before the step, the filter and the needle are carried one rung up and the step is redone
/// there (reduced_escalated raised); otherwise, with de-escalation on, the loop steps down once
/// the state, M-projected on the rung below, has fitted it for de_escalate_after_steps steps.
/// Returns the flags of the step(s) taken, the liver's own flags cleared.
HealthFlags step_liver(const OperatingLoopModel& model, OperatingLoopData& data, const TissueInputs& inputs) noexcept;

}  // namespace nav::detail
