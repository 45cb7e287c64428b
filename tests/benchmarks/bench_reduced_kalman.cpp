// Costs of the reduced-coordinate Kalman filter on the embedded liver (about 5000 tetrahedra,
// held at its attachments), observing the tumour centre (barycentric in its tetrahedron):
// predict (Gauss-Markov time update and the model's point), update (gated Kalman update in
// Joseph form) and estimate_point (position and 3x3 covariance), at r = 8, 16, 32, 64 modes.
// Each case reports call_us_median and call_us_p99 over its timed calls.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "nav/connective/organ_attachment.hpp"
#include "nav/fusion/reduced_kalman.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduction.hpp"
#include "step_times.hpp"

namespace {

/// The embedded liver, its scene, its 64 lowest modes and the tumour centre as an observed point.
struct Liver {
  nav::EmbeddedLiver liver = nav::make_embedded_liver(nav::kEmbeddedLiverElementSizeM);
  nav::TissueScene scene;
  nav::ReducedBasis modes;
  nav::ObservedPoint tumour;
};

const Liver& liver() {
  static const Liver built = [] {
    Liver l;
    l.scene.default_material = {5.0e3, 0.45, 1060.0};
    l.scene.fixed_nodes = l.liver.attachment_nodes;
    nav::ReductionOptions options;
    options.source = nav::ReducedBasisSource::linear_modes;
    options.force_kind = nav::ReducedForceKind::linear;
    options.basis_size = 64;
    l.modes = nav::make_modal_basis(l.liver.mesh, l.scene, nav::TissueSolverOptions{}, options).value();
    const auto located = nav::locate_in_tets(l.liver.mesh, l.liver.tumour_centre_m, "tumour_centre_m").value();
    l.tumour = {l.liver.mesh.tets[static_cast<std::size_t>(located.first)], located.second};
    return l;
  }();
  return built;
}

/// The filter of the first r modes, its data, and a reduced model's data a few steps under gravity.
struct Filter {
  nav::ReducedBasis basis;
  nav::ReducedModel reduced{nullptr};
  nav::ReducedKalmanModel model;
  std::optional<nav::ReducedKalmanData> data;
  std::optional<nav::ReducedData> reduced_data;
  explicit Filter(int r) {
    const Liver& l = liver();
    basis = l.modes;
    basis.basis_size = r;
    basis.basis.resize(3 * l.liver.mesh.nodes_m.size() * static_cast<std::size_t>(r));
    basis.column_values.resize(static_cast<std::size_t>(r));
    reduced = nav::make_reduced_model(l.liver.mesh, l.scene, nav::TissueSolverOptions{}, basis, {}).value();
    reduced_data.emplace(nav::make_reduced_data(reduced).value());
    for (int i = 0; i < 10; ++i) nav::step(reduced, *reduced_data, nav::TissueInputs{});
    nav::ReducedKalmanOptions options;
    options.correction_std.assign(static_cast<std::size_t>(r), 1e-3);
    options.correlation_time_s = 2.0;
    options.gate_chi_square = 1e12;  // every timed update is a full one
    const nav::ObservedPoint points[] = {l.tumour};
    model = nav::make_reduced_kalman_model(l.liver.mesh, basis, reduced, points, options).value();
    data.emplace(nav::make_reduced_kalman_data(model).value());
    nav::predict(model, *data, *reduced_data);
  }
};

/// Times `call(filter, i)` per call.
template <class Call>
void run(benchmark::State& state, Call&& call) {
  Filter f(static_cast<int>(state.range(0)));
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  std::int64_t i = 0;
  for (auto _ : state) state.SetIterationTime(nav::bench::time_call(us, [&] { call(f, i++); }));
  nav::bench::report_quantiles(state, "call", us);
  state.counters["healthy"] = f.data->health.healthy() ? 1.0 : 0.0;
}

void BM_ReducedKalmanPredict(benchmark::State& state) {
  run(state, [](Filter& f, std::int64_t) { nav::predict(f.model, *f.data, *f.reduced_data); });
}

void BM_ReducedKalmanUpdate(benchmark::State& state) {
  run(state, [](Filter& f, std::int64_t i) {
    const nav::Point3 z{f.data->model_points_m[0] + 1e-3 * static_cast<double>(i % 3 - 1), f.data->model_points_m[1],
                        f.data->model_points_m[2]};
    benchmark::DoNotOptimize(nav::update(f.model, *f.data, 0, z, i));
  });
}

void BM_ReducedKalmanEstimate(benchmark::State& state) {
  run(state, [](Filter& f, std::int64_t) { benchmark::DoNotOptimize(nav::estimate_point(f.model, *f.data, 0)); });
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int r : {8, 16, 32, 64}) b->Arg(r);
  b->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(20000);
}

BENCHMARK(BM_ReducedKalmanPredict)->Apply(sizes);
BENCHMARK(BM_ReducedKalmanUpdate)->Apply(sizes);
BENCHMARK(BM_ReducedKalmanEstimate)->Apply(sizes);

}  // namespace
