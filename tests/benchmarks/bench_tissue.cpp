// Step times of the tetrahedral FEM tissue on liver meshes of about 1k, 5k and 22k
// tetrahedra, for each rotation, integrator and solver, and the SOFA anchor scene
// (liverFine.vtu, implicit Euler dt 0.01 s, gravity, E 5000 Pa, nu 0.3, total mass 0.3 kg,
// the box of held nodes; SOFA: 1.6 s a step). Each case reports step_us_median and
// step_us_p99 over its timed steps.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/mesher/surface_domain.hpp"
#include "nav/tissue/node_selection.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace {

/// ../shared/data/liver/ next to the repository, found from this file's path (the benchmark
/// programs get no data-folder definition from the build).
std::string liver_dir() {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind('/')) + "/../../../shared/data/liver/";
}

/// The liver at about `tet_count` elements: liverFine.vtu itself for 22k, the mesher on the
/// liver surface for smaller counts. Built once per count.
const nav::TetMesh& liver_mesh(int tet_count) {
  static std::map<int, nav::TetMesh> meshes;
  auto found = meshes.find(tet_count);
  if (found != meshes.end()) return found->second;
  nav::TetMesh mesh;
  if (tet_count >= 20000) {
    mesh = nav::load_tet_mesh(liver_dir() + "liverFine.vtu", nav::LengthUnit::centimetre).value();
  } else {
    const nav::TriSurface surface =
        nav::load_surface(liver_dir() + "liver-smoothUV.obj", nav::LengthUnit::centimetre).value();
    nav::MesherOptions options;
    options.element_size_m = nav::element_size_for_tet_count_m(nav::enclosed_volume_m3(surface), tet_count);
    mesh = nav::make_tet_mesh(nav::SurfaceDomain(surface), options).value().mesh;
  }
  return meshes.emplace(tet_count, std::move(mesh)).first->second;
}

/// The anchor scene's supports and loads in SI: the box x in [0,2], y in [3,5], z in [-1,2] cm
/// held, gravity 9.81 m/s^2 along -y, 0.3 kg spread evenly over the nodes.
nav::TissueScene anchor_scene(const nav::TetMesh& mesh) {
  nav::TissueScene scene;
  scene.default_material = {5000.0, 0.3, 1000.0};
  scene.uniform_total_mass_kg = 0.3;
  scene.gravity_m_s2 = {0.0, -9.81, 0.0};
  auto held = nav::nodes_in_box(mesh, {{0.0, 0.03, -0.01}, {0.02, 0.05, 0.02}}, "held_box");
  if (!held.ok()) {  // a coarser mesh may miss the box: hold its nodes nearest the box's centre
    using nav::operator-;
    const nav::Point3 centre{0.01, 0.04, 0.005};
    std::vector<std::pair<double, std::int32_t>> by_distance;
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
      by_distance.emplace_back(nav::norm(mesh.nodes_m[n] - centre), static_cast<std::int32_t>(n));
    std::sort(by_distance.begin(), by_distance.end());
    for (std::size_t k = 0; k < std::min<std::size_t>(20, by_distance.size()); ++k) scene.fixed_nodes.push_back(by_distance[k].second);
  } else {
    scene.fixed_nodes = held.value();
  }
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
    const auto start = std::chrono::steady_clock::now();
    nav::step(model.value(), data.value(), inputs);
    const auto stop = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(stop - start).count();
    state.SetIterationTime(seconds);
    step_us.push_back(seconds * 1e6);
  }
  std::sort(step_us.begin(), step_us.end());
  state.counters["tets"] = static_cast<double>(model.value().tet_count());
  state.counters["step_us_median"] = step_us[step_us.size() / 2];
  state.counters["step_us_p99"] = step_us[std::min(step_us.size() - 1, (step_us.size() * 99) / 100)];
  state.counters["residual"] = data.value().report.solver_relative_residual;
  state.counters["cg_iters"] = data.value().report.solver_iterations;
  state.counters["healthy"] = data.value().health.healthy() ? 1.0 : 0.0;
  if (c.integrator == nav::Integrator::explicit_central_difference) state.counters["step_ms"] = options.step_s * 1e3;
}

using nav::ElementRotation;
using nav::Integrator;
using nav::LinearSolver;

void BM_CorotationalImplicitLdltWarped1(benchmark::State& s) { run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::ldlt_warped, 1}); }
void BM_CorotationalImplicitLdltWarped3(benchmark::State& s) { run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::ldlt_warped, 3}); }
void BM_CorotationalImplicitCgBlockJacobi20(benchmark::State& s) { run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::cg_block_jacobi, 20}); }
void BM_CorotationalImplicitCgJacobi20(benchmark::State& s) { run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::cg_jacobi, 20}); }
void BM_CorotationalQuasiStaticLdltWarped1(benchmark::State& s) { run_case(s, {ElementRotation::corotational, Integrator::quasi_static, LinearSolver::ldlt_warped, 1}); }
void BM_CorotationalExplicit(benchmark::State& s) { run_case(s, {ElementRotation::corotational, Integrator::explicit_central_difference, LinearSolver::ldlt_warped, 1}); }
void BM_LinearImplicitLdlt(benchmark::State& s) { run_case(s, {ElementRotation::none, Integrator::implicit_euler, LinearSolver::ldlt_warped, 1}); }
void BM_LinearExplicit(benchmark::State& s) { run_case(s, {ElementRotation::none, Integrator::explicit_central_difference, LinearSolver::ldlt_warped, 1}); }

// The SOFA anchor: liverFine.vtu (22019 tetrahedra), implicit corotational, reused warped factor.
void BM_SofaAnchorScene(benchmark::State& s) { run_case(s, {ElementRotation::corotational, Integrator::implicit_euler, LinearSolver::ldlt_warped, 1}); }

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
