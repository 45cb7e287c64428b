// Step times of the reduced ladder on liverFine.vtu (22019 tetrahedra, the "gravity" scene of
// nav::liver_scenes): rung 0 is the r = 16 leading vibration modes, rung 1 the r = 32 leading
// modes (nested), both corotational cubature on 64 evenly spaced tetrahedra of equal weight,
// implicit Euler at 1 ms with one Newton iteration and a frozen tangent; optionally the
// full-order corotational model on top (implicit Euler, warped LDL^T CG, 3 iterations).
// Cases: a step on rung 0 inside its envelope, the step that escalates (rung 0 flagged, so its
// tangent is rebuilt, then its step redone on the rung above), a step on the top reduced rung,
// and the step that escalates from it to the full order. The training envelope is set by hand:
// wide (never flags) or tiny (always flags), as speed does not depend on where it lies. Each
// case reports step_us_median and step_us_p99 over its timed steps. Skipped when
// ../shared/data is missing.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "liver_fine_modes.hpp"
#include "nav/reduced/reduced_ladder.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "step_times.hpp"

namespace {

using Liver = nav::bench::LiverFineModes;

/// liverFine, its gravity scene and its 32 lowest modes, built once (nullopt: data missing).
const std::optional<Liver>& liver() {
  static const std::optional<Liver> built = nav::bench::load_liver_fine_modes(32);
  return built;
}

constexpr double kStepS = 0.001;

/// The first r modes with 64 evenly spaced samples of equal weight and a uniform envelope.
nav::ReducedRungSpec rung(const Liver& l, int r, double q_bound) {
  constexpr int kSamples = 64;
  nav::ReducedBasis basis = l.modes;
  basis.basis_size = r;
  basis.force_kind = nav::ReducedForceKind::corotational_cubature;
  basis.basis.resize(3 * l.mesh.nodes_m.size() * static_cast<std::size_t>(r));
  basis.column_values.resize(static_cast<std::size_t>(r));
  for (int s = 0; s < kSamples; ++s) {
    basis.sample_tets.push_back(static_cast<std::int32_t>(static_cast<std::size_t>(s) * l.mesh.tets.size() / kSamples));
    basis.sample_weights.push_back(static_cast<double>(l.mesh.tets.size()) / kSamples);
  }
  basis.training_q_bound.assign(static_cast<std::size_t>(r), q_bound);
  nav::ReducedSolverOptions options;
  options.step_s = kStepS;
  return {std::move(basis), options};
}

constexpr double kWide = 1e9, kTiny = 1e-12;

/// The ladder r = 16 -> 32 (-> full order) with the given envelopes.
std::optional<nav::ReducedLadderModel> ladder(benchmark::State& state, double bound0, double bound1, bool full_order) {
  if (!liver()) {
    state.SkipWithError("shared data missing: ../shared/data/liver/liverFine.vtu");
    return std::nullopt;
  }
  const std::vector<nav::ReducedRungSpec> rungs{rung(*liver(), 16, bound0), rung(*liver(), 32, bound1)};
  nav::TissueSolverOptions solver;
  solver.step_s = kStepS;
  solver.cg_iterations = 3;  // with the warped LDL^T preconditioner
  auto model = nav::make_reduced_ladder_model(liver()->mesh, liver()->scene, solver, rungs, full_order, {});
  if (!model.ok()) {
    state.SkipWithError(model.error().describe().c_str());
    return std::nullopt;
  }
  return std::move(model).value();
}

/// Times steps under gravity, each started (untimed) on `start_rung`; a tiny envelope there
/// makes every step escalate.
void run(benchmark::State& state, int start_rung, double bound0, double bound1, bool full_order) {
  const auto model = ladder(state, bound0, bound1, full_order);
  if (!model) return;
  auto data = nav::make_reduced_ladder_data(*model).value();
  const nav::TissueInputs inputs;
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  std::int64_t escalations = 0;
  for (auto _ : state) {
    nav::move_to_rung(*model, data, start_rung);
    const std::int64_t before = data.escalations;
    state.SetIterationTime(nav::bench::time_call(us, [&] { nav::step(*model, data, inputs); }));
    escalations += data.escalations - before;
  }
  nav::bench::report_quantiles(state, "step", us);
  state.counters["escalated_fraction"] = static_cast<double>(escalations) / static_cast<double>(us.size());
}

void BM_LadderStepRung0(benchmark::State& s) { run(s, 0, kWide, kWide, false); }
void BM_LadderEscalatingStep(benchmark::State& s) { run(s, 0, kTiny, kWide, false); }
void BM_LadderStepTopReducedRung(benchmark::State& s) { run(s, 1, kWide, kWide, false); }
void BM_LadderEscalatingStepToFullOrder(benchmark::State& s) { run(s, 1, kWide, kTiny, true); }

BENCHMARK(BM_LadderStepRung0)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(3000);
BENCHMARK(BM_LadderEscalatingStep)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(3000);
BENCHMARK(BM_LadderStepTopReducedRung)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(3000);
BENCHMARK(BM_LadderEscalatingStepToFullOrder)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(40);

}  // namespace
