// Step times of the flexible needle: alone at 20, 30 and 40 elements, with 8, 16 and 32
// path constraints (20 and 30 elements, projected Gauss-Seidel with the scene's sweeps), and
// coupled to the reduced embedded liver (r = 16, tissue every tick) with 8, 16 and 32 path
// points at 20, 30 and 40 elements (32 points also per instruction set of the Gauss-Seidel
// kernels, and per sweep count at 30 elements), on the scenes of `navbench needle` (which also times the
// coupling to the full-order liver and writes the force profile). The needle alone and in the
// liver report step_us_median and step_us_p99 over their steps.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../../apps/navbench/bench_needle.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "step_times.hpp"

namespace {

using namespace navbench::needle_scenes;

void BM_NeedleAlone(benchmark::State& state) {
  const nav::NeedleModel model = nav::make_needle_model(needle(static_cast<int>(state.range(0)))).value();
  nav::NeedleData data = nav::make_needle_data(model, {}).value();
  nav::NeedleInputs inputs;
  inputs.tip_force_n = {0.0, 0.05, 0.0};
  int tick = 0;
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  for (auto _ : state) {
    inputs.base.position_m = {2e-5 * (tick++ % 20), 0.0, 0.0};
    nav::bench::time_call(us, [&] { nav::step(model, data, inputs); });
    benchmark::DoNotOptimize(data.positions_m.data());
  }
  nav::bench::report_quantiles(state, "step", us);
}
BENCHMARK(BM_NeedleAlone)->Arg(20)->Arg(30)->Arg(40)->Unit(benchmark::kMicrosecond);

void BM_NeedleWithPathConstraints(benchmark::State& state) {
  const nav::NeedleTissueModel model =
      nav::make_needle_tissue_model(needle(static_cast<int>(state.range(1))), capsule_and_parenchyma(0.004)).value();
  nav::NeedleTissueData data = nav::make_needle_tissue_data(model, {}).value();
  double x = 0.0;
  while (data.report.active_path_points < state.range(0)) drive_base_to(model, data, x += 1e-3);
  nav::NeedleTissueInputs inputs;
  int tick = 0;
  for (auto _ : state) {
    const int phase = tick % 40;
    inputs.needle.base.position_m = {x + 2e-5 * (phase < 20 ? phase - 10 : 30 - phase), 1e-3 * std::sin(1e-2 * tick),
                                     0.0};
    ++tick;
    nav::step(model, data, inputs);
    benchmark::DoNotOptimize(data.slot_forces.data());
  }
  state.counters["rows"] = data.row_count;
  state.counters["residual_m"] = data.report.residual_m;
}
BENCHMARK(BM_NeedleWithPathConstraints)->ArgsProduct({{8, 16, 32}, {20, 30}})->Unit(benchmark::kMicrosecond);

const EmbeddedLiverScene& the_liver() {
  static const EmbeddedLiverScene liver;
  return liver;
}

/// What the needle meets: the capsule's tangent plane at the entry (0), the capsule's surface
/// from the mesh (1), and that with the tumour's surface (2).
enum class Layers { plane = 0, capsule_surface = 1, capsule_and_tumour_surfaces = 2 };

/// The needle in the reduced liver with `points` path points, its Gauss-Seidel kernels of `isa`.
void run_in_reduced_liver(benchmark::State& state, int points, int elements, nav::KernelIsa isa,
                          int sweeps = nav::NeedleTissueScene{}.gauss_seidel_sweeps, Layers layers = Layers::plane) {
  if (!nav::kernel_isa_available(isa)) {
    state.SkipWithError("instruction set not available");
    return;
  }
  const EmbeddedLiverScene& liver = the_liver();
  static const nav::ReducedModel tissue = reduced_liver(liver);
  const Approach approach = approach_tumour(liver);
  nav::NeedleTissueScene scene =
      layers == Layers::plane
          ? liver_capsule(approach, kReducedPathSpacingM)
          : liver_surfaces(liver, approach, kReducedPathSpacingM, layers == Layers::capsule_and_tumour_surfaces);
  scene.kernel_isa = isa;
  scene.gauss_seidel_sweeps = sweeps;
  const nav::ReducedCoupledNeedleModel model =
      nav::make_coupled_needle_model(needle(elements), scene, tissue, liver.liver.mesh, 64, 1).value();
  nav::ReducedCoupledNeedleData data = nav::make_coupled_needle_data(model, approach.base_at(0.0)).value();
  const double advanced_m = insert_until(model, data, approach, points);
  int tick = 0;
  double largest_residual_m = 0.0;
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  for (auto _ : state) {
    const nav::NeedleInputs inputs{approach.wobbled_base(advanced_m, tick++), {}, {}};
    nav::bench::time_call(us, [&] { nav::step(model, data, inputs); });
    largest_residual_m = std::max(largest_residual_m, data.interaction.report.residual_m);
    benchmark::DoNotOptimize(data.interaction.slot_forces.data());
  }
  nav::bench::report_quantiles(state, "step", us);
  state.counters["rows"] = data.interaction.row_count;
  state.counters["largest_residual_m"] = largest_residual_m;
}

void BM_NeedleInReducedLiver(benchmark::State& state) {
  run_in_reduced_liver(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), nav::KernelIsa::best);
}
BENCHMARK(BM_NeedleInReducedLiver)->ArgsProduct({{8, 16, 32}, {20, 30, 40}})->Unit(benchmark::kMicrosecond);

/// 32 path points, 30 elements, the tissue stepped every tick: against the capsule's tangent
/// plane (0), its surface from the mesh (1: the nearest-point queries each tick, the surface
/// vertices in reach rebuilt and the hierarchy refitted each tissue step), and that with the
/// tumour's surface (2).
void BM_NeedleInReducedLiverLayers(benchmark::State& state) {
  run_in_reduced_liver(state, 32, 30, nav::KernelIsa::best, nav::NeedleTissueScene{}.gauss_seidel_sweeps,
                       static_cast<Layers>(state.range(0)));
}
BENCHMARK(BM_NeedleInReducedLiverLayers)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

/// A liver step's refresh of the capsule and tumour surfaces on the reduced liver: their
/// vertices rebuilt from q (every one, the most the needle's reach asks) and the hierarchies refitted.
void BM_SurfaceRefreshPerLiverStep(benchmark::State& state) {
  const EmbeddedLiverScene& liver = the_liver();
  static const nav::ReducedModel tissue = reduced_liver(liver);
  const Approach approach = approach_tumour(liver);
  const nav::ReducedCoupledNeedleModel model =
      nav::make_coupled_needle_model(needle(30), liver_surfaces(liver, approach, kReducedPathSpacingM, true), tissue,
                                     liver.liver.mesh, 64, 1)
          .value();
  nav::ReducedCoupledNeedleData data = nav::make_coupled_needle_data(model, approach.base_at(0.0)).value();
  insert_until(model, data, approach, 8);
  std::vector<std::int32_t> nodes;
  for (const nav::detail::SurfaceBvh& bvh : model.interaction.surface_bvhs)
    nodes.insert(nodes.end(), bvh.vertex_nodes.begin(), bvh.vertex_nodes.end());
  std::vector<double> values(3 * nodes.size());
  for (auto _ : state) {
    nav::reconstruct_displacements_m(tissue, data.tissue, nodes, values);
    for (std::size_t k = 0; k < nodes.size(); ++k)
      std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(3 * k), 3,
                  data.displacements_m.begin() + 3 * static_cast<std::ptrdiff_t>(nodes[k]));
    nav::refresh_surfaces(model.interaction, data.interaction, data.displacements_m);
    benchmark::DoNotOptimize(data.interaction.surface_boxes.data());
  }
  state.counters["vertices"] = static_cast<double>(nodes.size());
}
BENCHMARK(BM_SurfaceRefreshPerLiverStep)->Unit(benchmark::kMicrosecond);

/// What a new constraint node costs the needle on the full-order liver (about 5k tetrahedra,
/// corotational, implicit Euler over 10 ms): its response over one step along the three axes,
/// three solves with the rest factor (rest_step_response_m).
void BM_FullOrderNodeResponse(benchmark::State& state) {
  const EmbeddedLiverScene& liver = the_liver();
  nav::TissueSolverOptions options;
  options.step_s = 0.01;
  static const nav::TetFemModel tissue = nav::make_tet_fem_model(liver.liver.mesh, liver.scene(), options).value();
  const auto node = static_cast<std::int32_t>(nav::extract_boundary(liver.liver.mesh).mesh_node_of_vertex.front());
  std::vector<double> response(3 * liver.liver.mesh.nodes_m.size()), work(2 * tissue.free_dof_count());
  for (auto _ : state)
    for (int axis = 0; axis < 3; ++axis) {
      nav::rest_step_response_m(tissue, node, axis, response, work);
      benchmark::DoNotOptimize(response.data());
    }
  state.counters["free_dofs"] = static_cast<double>(tissue.free_dof_count());
  state.counters["factor_nonzeros"] = static_cast<double>(tissue.factor_nonzeros());
}
BENCHMARK(BM_FullOrderNodeResponse)->Unit(benchmark::kMicrosecond);

/// 32 path points per instruction set of the Gauss-Seidel kernels (1 baseline, 2 avx2, 3 avx512).
void BM_NeedleInReducedLiverKernels(benchmark::State& state) {
  run_in_reduced_liver(state, 32, static_cast<int>(state.range(0)), static_cast<nav::KernelIsa>(state.range(1)));
}
BENCHMARK(BM_NeedleInReducedLiverKernels)->ArgsProduct({{20, 30, 40}, {1, 2, 3}})->Unit(benchmark::kMicrosecond);

/// 32 path points, 30 elements, the best kernels, per Gauss-Seidel sweep count: the cost of a
/// sweep and the largest residual it leaves.
void BM_NeedleInReducedLiverSweeps(benchmark::State& state) {
  run_in_reduced_liver(state, 32, 30, nav::KernelIsa::best, static_cast<int>(state.range(0)));
}
BENCHMARK(BM_NeedleInReducedLiverSweeps)
    ->Arg(8)
    ->Arg(10)
    ->Arg(12)
    ->Arg(15)
    ->Arg(20)
    ->Arg(30)
    ->Iterations(4000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
