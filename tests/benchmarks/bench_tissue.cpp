// Step times of the tetrahedral FEM tissue on liver meshes of about 1k, 5k and 22k
// tetrahedra, for each rotation, integrator and solver, and the SOFA anchor scene
// (liverFine.vtu, implicit Euler dt 0.01 s, gravity, E 5000 Pa, nu 0.3, total mass 0.3 kg,
// the box of held nodes; SOFA: 1.6 s a step). Each case reports step_us_median and
// step_us_p99 over its timed steps.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "nav/tissue/liver_scenes.hpp"
#include "nav/tissue/node_selection.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "step_times.hpp"

namespace {

/// The liver at about `tet_count` elements (nav::load_liver_mesh), built once per count.
const nav::TetMesh& liver_mesh(int tet_count) {
  static std::map<int, nav::TetMesh> meshes;
  auto found = meshes.find(tet_count);
  if (found != meshes.end()) return found->second;
  return meshes.emplace(tet_count, nav::load_liver_mesh(NAV_SHARED_LIVER_DIR, tet_count).value()).first->second;
}

/// The anchor scene's supports and loads in SI: the held box x in [0,2], y in [3,5], z in
/// [-1,2] cm and gravity 9.81 m/s^2 along -y of nav::liver_scenes, with E 5000 Pa, nu 0.3 and
/// 0.3 kg spread evenly over the nodes.
nav::TissueScene anchor_scene(const nav::TetMesh& mesh) {
  nav::TissueScene scene = nav::liver_scenes(mesh).front().scene;
  scene.default_material = {5000.0, 0.3, 1000.0};
  scene.uniform_total_mass_kg = 0.3;
  return scene;
}

struct Case {
  nav::ElementRotation rotation;
  nav::Integrator integrator;
  nav::LinearSolver solver;
  int cg_iterations;
};

void run_case(benchmark::State& state, const Case& c) {
  const nav::TetMesh& mesh = liver_mesh(static_cast<int>(state.range(0)));
  nav::TissueSolverOptions options;
  options.rotation = c.rotation;
  options.integrator = c.integrator;
  options.solver = c.solver;
  options.cg_iterations = c.cg_iterations;
  options.step_s = 0.01;
  const nav::TissueScene scene = anchor_scene(mesh);
  if (c.integrator == nav::Integrator::explicit_central_difference) {
    const double limit_s = nav::make_tet_fem_model(mesh, scene, options).value().stable_step_s();
    options.step_s = 0.9 * limit_s;
  }
  auto model = nav::make_tet_fem_model(mesh, scene, options);
  if (!model.ok()) {
    state.SkipWithError(model.error().describe().c_str());
    return;
  }
  auto data = nav::make_tet_fem_data(model.value());
  std::vector<double> step_us;
  const nav::TissueInputs inputs;
  for (auto _ : state) {
    state.SetIterationTime(nav::bench::time_call(step_us, [&] { nav::step(model.value(), data.value(), inputs); }));
  }
  nav::bench::report_quantiles(state, "step", step_us);
  state.counters["tets"] = static_cast<double>(model.value().tet_count());
  state.counters["residual"] = data.value().report.solver_relative_residual;
  state.counters["cg_iters"] = data.value().report.solver_iterations;
  state.counters["healthy"] = data.value().health.healthy() ? 1.0 : 0.0;
  if (c.integrator == nav::Integrator::explicit_central_difference) state.counters["step_ms"] = options.step_s * 1e3;
}

using nav::ElementRotation;
using nav::Integrator;
using nav::LinearSolver;

void BM_CorotationalImplicitLdltWarped1(benchmark::State& s) {
  run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::ldlt_warped, 1});
}
void BM_CorotationalImplicitLdltWarped3(benchmark::State& s) {
  run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::ldlt_warped, 3});
}
void BM_CorotationalImplicitCgBlockJacobi20(benchmark::State& s) {
  run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::cg_block_jacobi, 20});
}
void BM_CorotationalImplicitCgJacobi20(benchmark::State& s) {
  run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::cg_jacobi, 20});
}
void BM_CorotationalQuasiStaticLdltWarped1(benchmark::State& s) {
  run_case(s, {ElementRotation::corotational, Integrator::quasi_static, LinearSolver::ldlt_warped, 1});
}
void BM_CorotationalExplicit(benchmark::State& s) {
  run_case(s, {ElementRotation::corotational, Integrator::explicit_central_difference, LinearSolver::ldlt_warped, 1});
}
void BM_LinearImplicitLdlt(benchmark::State& s) {
  run_case(s, {ElementRotation::none, Integrator::implicit_euler, LinearSolver::ldlt_warped, 1});
}
void BM_LinearExplicit(benchmark::State& s) {
  run_case(s, {ElementRotation::none, Integrator::explicit_central_difference, LinearSolver::ldlt_warped, 1});
}

// The SOFA anchor: liverFine.vtu (22019 tetrahedra), implicit corotational, reused warped factor.
void BM_SofaAnchorScene(benchmark::State& s) {
  run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::ldlt_warped, 1});
}

void sizes(benchmark::internal::Benchmark* b) {
  b->Arg(1000)->Arg(5000)->Arg(22019)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(40);
}

BENCHMARK(BM_SofaAnchorScene)->Arg(22019)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(100);
BENCHMARK(BM_CorotationalImplicitLdltWarped1)->Apply(sizes);
BENCHMARK(BM_CorotationalImplicitLdltWarped3)->Apply(sizes);
BENCHMARK(BM_CorotationalImplicitCgBlockJacobi20)->Apply(sizes);
BENCHMARK(BM_CorotationalImplicitCgJacobi20)->Apply(sizes);
BENCHMARK(BM_CorotationalQuasiStaticLdltWarped1)->Apply(sizes);
BENCHMARK(BM_CorotationalExplicit)->Apply(sizes);
BENCHMARK(BM_LinearImplicitLdlt)->Apply(sizes);
BENCHMARK(BM_LinearExplicit)->Apply(sizes);

}  // namespace
