#include "nav/core/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

#include "support/allocation_guard.hpp"

namespace nav {

TEST(SpscRing, IsFirstInFirstOutAcrossWrapAround) {
  SpscRing<int, 4> ring;
  int out = 0;
  EXPECT_FALSE(ring.try_pop(out));
  for (int round = 0; round < 5; ++round) {
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(ring.try_push(round * 10 + i));
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(ring.try_pop(out));
      EXPECT_EQ(out, round * 10 + i);
    }
  }
  EXPECT_EQ(ring.size(), 0u);
}

TEST(SpscRing, RefusesWhenFullAndCountsTheLoss) {
  SpscRing<int, 4> ring;
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.try_push(i));
  EXPECT_FALSE(ring.try_push(99));
  EXPECT_FALSE(ring.try_push(100));
  EXPECT_EQ(ring.dropped(), 2u);
  int out = -1;
  ASSERT_TRUE(ring.try_pop(out));
  EXPECT_EQ(out, 0);  // the oldest survived; the refused ones were never written
  EXPECT_TRUE(ring.try_push(4));
}

TEST(SpscRing, PushAndPopAllocateNothing) {
  SpscRing<std::uint64_t, 64> ring;
  testing::AllocationGuard guard;
  std::uint64_t out = 0;
  for (std::uint64_t i = 0; i < 10'000; ++i) {
    ring.try_push(i);
    ring.try_pop(out);
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_EQ(out, 9'999u);
}

// Two threads, every item carries its sequence number and a checksum: the consumer must
// see each item exactly once, in order, intact. Run under ThreadSanitizer in CI.
TEST(SpscRing, TwoThreadsDeliverEveryItemInOrder) {
  struct Item {
    std::uint64_t sequence;
    std::uint64_t payload[6];
    std::uint64_t checksum;
  };
  constexpr std::uint64_t kItems = 200'000;
  static SpscRing<Item, 256> ring;
  std::thread producer([] {
    for (std::uint64_t i = 0; i < kItems;) {
      Item item{i, {i, i * 3, i * 5, i * 7, i * 11, i * 13}, 0};
      for (std::uint64_t word : item.payload) item.checksum ^= word * 0x9E3779B97F4A7C15ull;
      if (ring.try_push(item)) ++i;
    }
  });
  std::uint64_t expected = 0;
  bool intact = true;
  Item item{};
  while (expected < kItems) {
    if (!ring.try_pop(item)) continue;
    std::uint64_t checksum = 0;
    for (std::uint64_t word : item.payload) checksum ^= word * 0x9E3779B97F4A7C15ull;
    intact = intact && item.sequence == expected && checksum == item.checksum;
    ++expected;
  }
  producer.join();
  EXPECT_TRUE(intact);
  EXPECT_EQ(expected, kItems);
}

}  // namespace nav
