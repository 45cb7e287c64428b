#include "nav/core/triple_buffer.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>

#include "support/allocation_guard.hpp"

namespace nav {

namespace {
// A sample whose fields must always agree: a torn read would mix two versions.
struct Sample {
  std::uint64_t version = 0;
  std::uint64_t copies[15] = {};
  bool consistent() const {
    for (std::uint64_t copy : copies)
      if (copy != version) return false;
    return true;
  }
};
Sample make_sample(std::uint64_t version) {
  Sample sample;
  sample.version = version;
  for (auto& copy : sample.copies) copy = version;
  return sample;
}
}  // namespace

TEST(TripleBuffer, ReaderGetsTheLatestPublishedValueOnce) {
  TripleBuffer<int> buffer;
  EXPECT_FALSE(buffer.update());
  EXPECT_EQ(buffer.read(), 0);
  buffer.write(1);
  buffer.write(2);
  buffer.write(3);
  EXPECT_TRUE(buffer.update());
  EXPECT_EQ(buffer.read(), 3);    // the latest, not the oldest
  EXPECT_FALSE(buffer.update());  // nothing newer
  EXPECT_EQ(buffer.read(), 3);
  buffer.write_slot() = 4;
  buffer.publish();
  EXPECT_TRUE(buffer.update());
  EXPECT_EQ(buffer.read(), 4);
}

TEST(TripleBuffer, WriteAndUpdateAllocateNothing) {
  TripleBuffer<Sample> buffer;
  testing::AllocationGuard guard;
  for (std::uint64_t v = 1; v < 1000; ++v) {
    buffer.write(make_sample(v));
    buffer.update();
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_EQ(buffer.read().version, 999u);
}

// The writer publishes as fast as it can; the reader must never see a torn sample nor a
// version older than one it already saw. Run under ThreadSanitizer in CI.
TEST(TripleBuffer, TwoThreadsNeverTearNorGoBack) {
  constexpr std::uint64_t kVersions = 300'000;
  static TripleBuffer<Sample> buffer;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::uint64_t v = 1; v <= kVersions; ++v) {
      Sample& slot = buffer.write_slot();
      slot = make_sample(v);
      buffer.publish();
    }
    done.store(true, std::memory_order_release);
  });
  std::uint64_t last_seen = 0;
  std::uint64_t updates = 0;
  bool ok = true;
  for (;;) {
    const bool writer_finished = done.load(std::memory_order_acquire);
    if (!buffer.update()) {
      if (writer_finished) break;
      continue;
    }
    const Sample& sample = buffer.read();
    ok = ok && sample.consistent() && sample.version > last_seen;
    last_seen = sample.version;
    ++updates;
  }
  writer.join();
  EXPECT_TRUE(ok);
  EXPECT_EQ(buffer.read().version, kVersions);
  EXPECT_GT(updates, 0u);
}

}  // namespace nav
