// Step times of the reduced liver on liverFine.vtu (22019 tetrahedra, the "gravity" scene of
// nav::liver_scenes): a corotational cubature of r = 8, 16, 32, 64 vibration modes on
// m = 64, 128, 164, 195 sampled tetrahedra, implicit Euler with one Newton iteration, the
// rest tangent frozen or rebuilt every step; the linear reduced step; and the reconstruction
// of 2000 nodes (the 1603 surface nodes plus interior ones), from the row-major basis and from
// a display set. The samples are evenly spaced with
// equal weights (speed does not depend on which tetrahedra ECSW picks); the frozen r = 16 step
// under a needle's 32 point forces without and with the error estimate. Each case reports
// step_us_median and step_us_p99 over its timed steps. Skipped when ../shared/data is missing.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "liver_fine_modes.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "step_times.hpp"

namespace {

using Liver = nav::bench::LiverFineModes;

/// liverFine, its gravity scene and its 64 lowest modes, built once (nullopt: data missing).
const std::optional<Liver>& liver() {
  static const std::optional<Liver> built = nav::bench::load_liver_fine_modes(64);
  return built;
}

/// The first r modes with m evenly spaced samples of equal weight.
nav::ReducedBasis truncated(const Liver& l, int r, int m, nav::ReducedForceKind kind) {
  nav::ReducedBasis basis = l.modes;
  basis.basis_size = r;
  basis.force_kind = kind;
  basis.basis.resize(3 * l.mesh.nodes_m.size() * static_cast<std::size_t>(r));
  basis.column_values.resize(static_cast<std::size_t>(r));
  for (int s = 0; s < m && kind != nav::ReducedForceKind::linear; ++s) {
    basis.sample_tets.push_back(
        static_cast<std::int32_t>(static_cast<std::size_t>(s) * l.mesh.tets.size() / static_cast<std::size_t>(m)));
    basis.sample_weights.push_back(static_cast<double>(l.mesh.tets.size()) / m);
  }
  return basis;
}

/// Times the steps of the reduced model of `basis` on `scene` under `inputs`.
void time_steps(benchmark::State& state, const nav::TissueScene& scene, const nav::ReducedBasis& basis,
                const nav::ReducedSolverOptions& options, const nav::TissueInputs& inputs) {
  auto model = nav::make_reduced_model(liver()->mesh, scene, nav::TissueSolverOptions{}, basis, options);
  if (!model.ok()) {
    state.SkipWithError(model.error().describe().c_str());
    return;
  }
  auto data = nav::make_reduced_data(model.value()).value();
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  for (auto _ : state)
    state.SetIterationTime(nav::bench::time_call(us, [&] { nav::step(model.value(), data, inputs); }));
  nav::bench::report_quantiles(state, "step", us);
  state.counters["healthy"] = data.health.healthy() ? 1.0 : 0.0;
  state.counters["memory_kb"] = static_cast<double>(model.value().memory_bytes()) / 1024.0;
}

void run_step(benchmark::State& state, nav::ReducedForceKind kind, bool frozen) {
  if (!liver()) {
    state.SkipWithError("shared data missing: ../shared/data/liver/liverFine.vtu");
    return;
  }
  const int r = static_cast<int>(state.range(0)), m = static_cast<int>(state.range(1));
  nav::ReducedSolverOptions options;
  options.frozen_tangent = frozen;
  options.step_s = 0.001;
  time_steps(state, liver()->scene, truncated(*liver(), r, m, kind), options, nav::TissueInputs{});
}

/// The frozen corotational step (r = 16, 164 samples) under 32 point forces on 32 nodes (a
/// needle's), without (0) and with (1) an error estimate (a synthetic calibration: its cost
/// does not depend on the values).
void BM_ReducedErrorEstimate(benchmark::State& state) {
  if (!liver()) {
    state.SkipWithError("shared data missing: ../shared/data/liver/liverFine.vtu");
    return;
  }
  nav::ReducedBasis basis = truncated(*liver(), 16, 164, nav::ReducedForceKind::corotational_cubature);
  if (state.range(0) == 1) {
    basis.error_calibration.missing_compliance_m_per_n.assign(6 * liver()->mesh.nodes_m.size(), 1e-3);
    basis.error_calibration.gain = 1.0;
  }
  nav::TissueScene scene = liver()->scene;
  scene.max_point_forces = 32;
  std::vector<nav::PointForce> forces;
  for (std::int32_t k = 0; k < 32; ++k) forces.push_back({1000 + 97 * k, {0.0, 0.001, -0.002}});
  nav::TissueInputs inputs;
  inputs.point_forces = forces;
  nav::ReducedSolverOptions options;
  options.step_s = 0.001;
  time_steps(state, scene, basis, options, inputs);
}

void BM_ReducedCorotationalFrozen(benchmark::State& s) {
  run_step(s, nav::ReducedForceKind::corotational_cubature, true);
}
void BM_ReducedCorotationalTangent(benchmark::State& s) {
  run_step(s, nav::ReducedForceKind::corotational_cubature, false);
}
void BM_ReducedLinear(benchmark::State& s) { run_step(s, nav::ReducedForceKind::linear, true); }

/// 2000 nodes spread over the mesh (the 1603 surface nodes are among them on liverFine).
std::vector<std::int32_t> display_nodes() {
  std::vector<std::int32_t> nodes(2000);
  const std::size_t n = liver()->mesh.nodes_m.size();
  for (std::size_t k = 0; k < nodes.size(); ++k) nodes[k] = static_cast<std::int32_t>(k * n / nodes.size());
  return nodes;
}

/// Times reconstruct(model, data, out) on a linear model of r modes after 10 steps.
template <class Reconstruct>
void run_reconstruction(benchmark::State& state, Reconstruct&& reconstruct) {
  if (!liver()) {
    state.SkipWithError("shared data missing: ../shared/data/liver/liverFine.vtu");
    return;
  }
  const int r = static_cast<int>(state.range(0));
  auto model = nav::make_reduced_model(liver()->mesh, liver()->scene, nav::TissueSolverOptions{},
                                       truncated(*liver(), r, 0, nav::ReducedForceKind::linear), {})
                   .value();
  auto data = nav::make_reduced_data(model).value();
  nav::TissueInputs inputs;
  for (int i = 0; i < 10; ++i) nav::step(model, data, inputs);
  std::vector<double> out(3 * display_nodes().size());
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  reconstruct(model, data, out);  // builds what the reconstruction needs outside the timing
  for (auto _ : state)
    state.SetIterationTime(nav::bench::time_call(us, [&] {
      reconstruct(model, data, out);
      benchmark::DoNotOptimize(out.data());
    }));
  nav::bench::report_quantiles(state, "step", us);
}

/// reconstruct_displacements_m on a list of nodes (the basis rows, row-major).
void BM_ReconstructNodes(benchmark::State& state) {
  const std::vector<std::int32_t> nodes = display_nodes();
  run_reconstruction(state,
                     [&](const nav::ReducedModel& model, const nav::ReducedData& data, std::vector<double>& out) {
                       nav::reconstruct_displacements_m(model, data, nodes, out);
                     });
}

/// reconstruct_display_m on a display set of the same nodes (panels built once).
void BM_ReconstructDisplay(benchmark::State& state) {
  std::optional<nav::ReducedDisplaySet> display;
  run_reconstruction(state,
                     [&](const nav::ReducedModel& model, const nav::ReducedData& data, std::vector<double>& out) {
                       if (!display) display = nav::make_reduced_display_set(model, display_nodes()).value();
                       nav::reconstruct_display_m(model, data, *display, out);
                     });
}

/// r = 8, 16, 32, 64 at m = 64 and 128 and at the cubature sizes ECSW reaches on liverFine
/// for the accuracy bounds (164 samples at r = 16, 195 at r = 32).
void cubature_cases(benchmark::internal::Benchmark* b) {
  for (int r : {8, 16, 32, 64})
    for (int m : {64, 128, 164, 195}) b->Args({r, m});
  b->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(3000);
}

void reconstruction_cases(benchmark::internal::Benchmark* b) {
  b->Arg(8)->Arg(16)->Arg(32)->Arg(64)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(3000);
}

BENCHMARK(BM_ReducedCorotationalFrozen)->Apply(cubature_cases);
BENCHMARK(BM_ReducedCorotationalTangent)->Apply(cubature_cases);
BENCHMARK(BM_ReducedLinear)
    ->Args({8, 0})
    ->Args({16, 0})
    ->Args({32, 0})
    ->Args({64, 0})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(3000);
BENCHMARK(BM_ReducedErrorEstimate)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(3000);
BENCHMARK(BM_ReconstructNodes)->Apply(reconstruction_cases);
BENCHMARK(BM_ReconstructDisplay)->Apply(reconstruction_cases);

}  // namespace
