// Mesher times: the real liver surface (../shared/data/liver/liver-smoothUV.obj, centimetres)
// at about 1k, 5k, 20k and 80k tetrahedra, and the embedded default liver. Each case reports
// the element and node counts it made.
#include <benchmark/benchmark.h>

#include <optional>
#include <string>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/obj_reader.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/mesher/surface_domain.hpp"

namespace {

/// The liver surface, read once from ../shared/data/liver/ beside the repository.
const std::optional<nav::TriSurface>& liver_surface() {
  static const std::optional<nav::TriSurface> surface = [] {
    const std::string path = NAV_SHARED_LIVER_DIR "/liver-smoothUV.obj";
    auto loaded = nav::load_obj_surface(path, nav::LengthUnit::centimetre);
    return loaded.ok() ? std::optional<nav::TriSurface>(loaded.value()) : std::nullopt;
  }();
  return surface;
}

void BM_MeshLiverSurface(benchmark::State& state) {
  if (!liver_surface()) {
    state.SkipWithError("shared data missing: ../shared/data/liver/liver-smoothUV.obj");
    return;
  }
  const nav::SurfaceDomain domain(*liver_surface());
  const nav::MesherOptions options{.element_size_m = nav::element_size_for_tet_count_m(
                                       nav::enclosed_volume_m3(*liver_surface()), static_cast<double>(state.range(0))),
                                   .fitting = {}};
  std::size_t tets = 0;
  std::size_t nodes = 0;
  for (auto _ : state) {
    const auto made = nav::make_tet_mesh(domain, options);
    benchmark::DoNotOptimize(made.value().mesh.nodes_m.data());
    tets = made.value().mesh.tets.size();
    nodes = made.value().mesh.nodes_m.size();
  }
  state.counters["tets"] = static_cast<double>(tets);
  state.counters["nodes"] = static_cast<double>(nodes);
}
BENCHMARK(BM_MeshLiverSurface)->Arg(1000)->Arg(5000)->Arg(20000)->Arg(80000)->Unit(benchmark::kMillisecond);

void BM_EmbeddedLiver(benchmark::State& state) {
  std::size_t tets = 0;
  for (auto _ : state) {
    const nav::EmbeddedLiver liver = nav::make_embedded_liver(nav::kEmbeddedLiverElementSizeM);
    benchmark::DoNotOptimize(liver.mesh.nodes_m.data());
    tets = liver.mesh.tets.size();
  }
  state.counters["tets"] = static_cast<double>(tets);
}
BENCHMARK(BM_EmbeddedLiver)->Unit(benchmark::kMillisecond);

}  // namespace
