#include "nav/core/arena.hpp"

#include <gtest/gtest.h>

#include <cstdint>

#include "support/allocation_guard.hpp"

namespace nav {

TEST(Arena, CarvesAlignedZeroedSpansFromOneBlock) {
  Arena arena("tissue", 1024);
  auto bytes = arena.allocate<std::uint8_t>("flags", 3);
  auto doubles = arena.allocate<double>("positions_m", 10);
  ASSERT_TRUE(bytes.ok());
  ASSERT_TRUE(doubles.ok());
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(doubles.value().data()) % alignof(double), 0u);
  for (double value : doubles.value()) EXPECT_EQ(value, 0.0);
  EXPECT_GE(arena.used_bytes(), 3 + 10 * sizeof(double));
  EXPECT_LE(arena.used_bytes(), 3 + 10 * sizeof(double) + alignof(double));
  // The spans do not overlap.
  EXPECT_LE(bytes.value().data() + 3, reinterpret_cast<std::uint8_t*>(doubles.value().data()));
}

TEST(Arena, AskingForMoreThanDeclaredSaysWhatAndHowMuch) {
  Arena arena("needle", 100);
  ASSERT_TRUE(arena.allocate<double>("shape_m", 10).ok());
  auto too_much = arena.allocate<double>("forces_n", 4);
  ASSERT_FALSE(too_much.ok());
  const std::string text = too_much.error().describe();
  EXPECT_NE(text.find("arena 'needle'"), std::string::npos) << text;
  EXPECT_NE(text.find("forces_n"), std::string::npos) << text;
  EXPECT_NE(text.find("4 x 8 bytes"), std::string::npos) << text;
  EXPECT_NE(text.find("20 of 100 bytes are left"), std::string::npos) << text;
  // The failed request took nothing.
  EXPECT_EQ(arena.used_bytes(), 80u);
  EXPECT_TRUE(arena.allocate<double>("forces_n", 2).ok());
}

TEST(Arena, HugeCountsAreRefusedWithoutOverflow) {
  Arena arena("tiny", 64);
  volatile std::size_t huge_count = static_cast<std::size_t>(-1) / 4;  // opaque to the optimiser
  auto result = arena.allocate<double>("too_many", huge_count);
  EXPECT_FALSE(result.ok());
  EXPECT_EQ(arena.used_bytes(), 0u);
}

TEST(Arena, CarvingAllocatesNothingOnTheHeap) {
  Arena arena("scene", 4096);
  testing::AllocationGuard guard;
  auto first = arena.allocate<float>("a", 100);
  auto second = arena.allocate<std::int64_t>("b", 100);
  EXPECT_TRUE(first.ok() && second.ok());
  EXPECT_EQ(guard.allocations(), 0u);
}

TEST(ArenaPlan, DeclaredFootprintIsEnoughForTheBuffers) {
  ArenaPlan plan;
  plan.add<std::uint8_t>(3).add<double>(10).add<std::int32_t>(7).add<double>(1);
  Arena arena("planned", plan.bytes());
  EXPECT_TRUE(arena.allocate<std::uint8_t>("a", 3).ok());
  EXPECT_TRUE(arena.allocate<double>("b", 10).ok());
  EXPECT_TRUE(arena.allocate<std::int32_t>("c", 7).ok());
  EXPECT_TRUE(arena.allocate<double>("d", 1).ok());
  EXPECT_FALSE(arena.allocate<double>("one more", 8).ok());
}

TEST(ArenaPlan, WiderAlignmentsAreCarvedAndDeclaredAlike) {
  ArenaPlan plan;
  plan.add<std::uint8_t>(3).add<double>(5, 64).add<std::uint8_t>(1).add<double>(9, 64);
  Arena arena("lanes", plan.bytes());
  ASSERT_TRUE(arena.allocate<std::uint8_t>("a", 3).ok());
  auto first = arena.allocate<double>("b", 5, 64);
  ASSERT_TRUE(arena.allocate<std::uint8_t>("c", 1).ok());
  auto second = arena.allocate<double>("d", 9, 64);
  ASSERT_TRUE(first.ok() && second.ok());
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(first.value().data()) % 64, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(second.value().data()) % 64, 0u);
  // An alignment below the type's own keeps the type's.
  Arena small("small", 64);
  ASSERT_TRUE(small.allocate<std::uint8_t>("a", 1).ok());
  auto aligned = small.allocate<double>("b", 1, 1);
  ASSERT_TRUE(aligned.ok());
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned.value().data()) % alignof(double), 0u);
}

}  // namespace nav
