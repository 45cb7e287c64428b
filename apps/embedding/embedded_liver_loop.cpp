// Station software embedding navrt without DDS: its own real-time thread steps the embedded
// liver at a fixed rate while a probe presses above the tumour, and hands the tumour's
// position to the rest of the software through a lock-free latest-value buffer, which the
// main thread reads as a display would. Prints the tumour's motion and the loop's timing.
//   embedded_liver_loop [TICKS]   (default 200 ticks of 10 ms)
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "nav/core/clock.hpp"
#include "nav/core/fixed_rate_timer.hpp"
#include "nav/core/triple_buffer.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace {

constexpr nav::TimeNs kPeriodNs = 10'000'000;  // the tissue rate: 100 Hz

/// What the real-time thread publishes after every tick.
struct TumourSample {
  std::int64_t tick = -1;
  double position_m[3] = {0.0, 0.0, 0.0};
  std::uint32_t health_bits = 0;
};

/// The mesh node closest to `point`: the tumour's centre is followed through it.
std::int32_t closest_node(const nav::TetMesh& mesh, const nav::Point3& point) {
  std::int32_t best = 0;
  double best_d2 = INFINITY;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) d2 += (mesh.nodes_m[n][k] - point[k]) * (mesh.nodes_m[n][k] - point[k]);
    if (d2 < best_d2) best_d2 = d2, best = static_cast<std::int32_t>(n);
  }
  return best;
}

/// The height (y, anterior) of the liver's surface above `point`: where the probe touches.
double surface_y_above_m(const nav::TetMesh& mesh, const nav::Point3& point) {
  double top_m = point[1];
  for (const nav::Point3& node : mesh.nodes_m) {
    if (std::hypot(node[0] - point[0], node[2] - point[2]) < 0.015) top_m = std::max(top_m, node[1]);
  }
  return top_m;
}

}  // namespace

int main(int argc, char** argv) {
  const long ticks = argc > 1 ? std::strtol(argv[1], nullptr, 10) : 200;
  if (ticks <= 0) {
    std::fprintf(stderr, "usage: embedded_liver_loop [TICKS > 0]\n");
    return 2;
  }
  // Init time: build the model and its data once; may allocate and fail with a clear error.
  const nav::EmbeddedLiver liver = nav::make_embedded_liver(0.02);
  nav::TissueScene scene;
  scene.default_material = {5000.0, 0.45, 1060.0};
  scene.fixed_nodes = liver.attachment_nodes;
  scene.probe_stiffness_n_m = 500.0;
  scene.gravity_m_s2 = {0.0, 0.0, 0.0};  // the mesh was segmented with gravity already acting
  nav::TissueSolverOptions options;
  options.step_s = 1e-9 * kPeriodNs;
  options.rayleigh_mass_per_s = 1.0;
  auto model = nav::make_tet_fem_model(liver.mesh, scene, options);
  if (!model.ok()) {
    std::fprintf(stderr, "embedded_liver_loop: %s\n", model.error().describe().c_str());
    return 1;
  }
  auto data = nav::make_tet_fem_data(model.value());
  if (!data.ok()) {
    std::fprintf(stderr, "embedded_liver_loop: %s\n", data.error().describe().c_str());
    return 1;
  }
  const std::int32_t tumour_node = closest_node(liver.mesh, liver.tumour_centre_m);
  const nav::Point3 rest = liver.mesh.nodes_m[static_cast<std::size_t>(tumour_node)];
  constexpr double kProbeRadiusM = 0.015;
  const double probe_touch_y_m = surface_y_above_m(liver.mesh, rest) + kProbeRadiusM;
  std::printf("liver: %zu tetrahedra, tumour followed at node %d\n", liver.mesh.tets.size(), tumour_node);

  nav::TripleBuffer<TumourSample> tumour;
  std::atomic<bool> done{false};
  nav::MonotonicClock clock;
  nav::FixedRateTimer timer(clock, kPeriodNs, clock.now_ns() + kPeriodNs);

  // The real-time thread: step, publish, wait. Nothing here allocates, locks or throws.
  std::thread realtime([&] {
    nav::TissueInputs inputs;
    for (long k = 0; k < ticks; ++k) {
      const nav::Tick tick = timer.wait_next_tick();
      const double pressed_m = 0.01 * std::min(1.0, static_cast<double>(k) / 100.0);  // 10 mm over 1 s
      inputs.probe = {true, {rest[0], probe_touch_y_m - pressed_m, rest[2]}, kProbeRadiusM};
      nav::step(model.value(), data.value(), inputs);
      TumourSample& sample = tumour.write_slot();
      sample.tick = tick.index;
      for (int i = 0; i < 3; ++i) sample.position_m[i] = data.value().positions_m[3 * tumour_node + i];
      sample.health_bits = data.value().health.bits();
      tumour.publish();
    }
    done.store(true, std::memory_order_release);
  });

  // The rest of the station: read the latest sample whenever it likes (here: every 100 ms).
  TumourSample latest;
  while (!done.load(std::memory_order_acquire)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (tumour.update()) latest = tumour.read();
  }
  realtime.join();
  if (tumour.update()) latest = tumour.read();
  double moved_m = 0.0;
  for (int i = 0; i < 3; ++i) moved_m += (latest.position_m[i] - rest[i]) * (latest.position_m[i] - rest[i]);
  moved_m = std::sqrt(moved_m);
  std::printf("ticks: %ld, deadline misses: %lld, skipped: %lld\n", ticks,
              static_cast<long long>(timer.deadline_misses()), static_cast<long long>(timer.skipped_ticks()));
  std::printf("tumour moved %.3f mm (health bits 0x%x)\n", 1e3 * moved_m, latest.health_bits);
  return std::isfinite(moved_m) && latest.health_bits == 0 ? 0 : 1;
}
