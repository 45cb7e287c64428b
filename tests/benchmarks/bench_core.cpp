// Costs of the core hand-off primitives on one thread (no contention): what the
// real-time thread pays per push/pop or per publish/update.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>

#include "nav/core/arena.hpp"
#include "nav/core/clock.hpp"
#include "nav/core/spsc_ring.hpp"
#include "nav/core/triple_buffer.hpp"

namespace {

struct PoseSample {  // the size of a tool pose: id, time, position, quaternion, quality
  std::int64_t timestamp_ns;
  std::int32_t tool_id;
  double position_m[3];
  double quaternion[4];
  double quality;
};

void BM_SpscRingPushPop(benchmark::State& state) {
  static nav::SpscRing<PoseSample, 256> ring;
  PoseSample sample{};
  PoseSample out{};
  for (auto _ : state) {
    sample.timestamp_ns++;
    ring.try_push(sample);
    ring.try_pop(out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_SpscRingPushPop);

void BM_TripleBufferPublishUpdate(benchmark::State& state) {
  static nav::TripleBuffer<PoseSample> buffer;
  PoseSample sample{};
  for (auto _ : state) {
    sample.timestamp_ns++;
    buffer.write(sample);
    buffer.update();
    benchmark::DoNotOptimize(buffer.read());
  }
}
BENCHMARK(BM_TripleBufferPublishUpdate);

void BM_MonotonicClockNow(benchmark::State& state) {
  nav::MonotonicClock clock;
  for (auto _ : state) benchmark::DoNotOptimize(clock.now_ns());
}
BENCHMARK(BM_MonotonicClockNow);

void BM_ArenaCarve64Buffers(benchmark::State& state) {
  for (auto _ : state) {
    nav::Arena arena("bench", 64 * 1024);
    for (int i = 0; i < 64; ++i) benchmark::DoNotOptimize(arena.allocate<double>("buffer", 100));
  }
}
BENCHMARK(BM_ArenaCarve64Buffers);

}  // namespace
