// Step time of the frame-based connective tissue (implicit Euler) against its number of
// frames and integration points: ligament blocks of n x n x n frames 1 cm apart, 2 or 3
// Gauss points per cell axis, 60 CG iterations (the paper's setting) or the banded Cholesky.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "nav/connective/frame_tissue_model.hpp"

namespace {

void BM_FrameTissueStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  nav::FrameGrid grid;
  grid.counts = {n, n, n};
  grid.spacing_m = {0.01, 0.01, 0.01};
  grid.points_per_cell_axis = static_cast<int>(state.range(1));
  nav::FrameTissueScene scene;
  scene.layout = nav::make_grid_layout(grid).value();
  scene.material = {1e5, 0.45, 1100.0};
  for (std::size_t f = 0; f < scene.layout.frames_m.size(); ++f)
    if (scene.layout.frames_m[f][2] > 0.01 * (n - 1) - 1e-9)
      scene.supports.fixed_frames.push_back(static_cast<std::int32_t>(f));
  nav::FrameTissueOptions options;
  options.solver = state.range(2) == 0 ? nav::FrameSolver::cg_block_jacobi : nav::FrameSolver::banded_cholesky;
  options.rayleigh_mass_per_s = 1.0;
  const nav::FrameTissueModel model = nav::make_frame_tissue_model(scene, options).value();
  nav::FrameTissueData data = nav::make_frame_tissue_data(model).value();
  for (auto _ : state) {
    nav::step(model, data, {});
    benchmark::DoNotOptimize(data.positions_m.data());
  }
  state.counters["frames"] = static_cast<double>(model.frame_count());
  state.counters["points"] = static_cast<double>(model.point_count());
  state.counters["s_per_point_step"] =
      benchmark::Counter(static_cast<double>(model.point_count()),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_FrameTissueStep)
    ->ArgNames({"n", "gauss", "banded"})
    ->Args({3, 2, 0})
    ->Args({4, 2, 0})
    ->Args({5, 2, 0})
    ->Args({6, 2, 0})
    ->Args({4, 3, 0})
    ->Args({6, 3, 0})
    ->Args({3, 2, 1})
    ->Args({4, 2, 1})
    ->Args({5, 2, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
