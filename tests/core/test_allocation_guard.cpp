// Self-test of the allocation guard: it must see every kind of heap allocation, or the
// "step functions never allocate" tests that rely on it prove nothing.
#include "support/allocation_guard.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace nav::testing {
namespace {

// Keeps the optimiser from removing an allocation whose result is unused.
template <typename T>
void keep(T&& value) {
  asm volatile("" : : "g"(&value) : "memory");
}

TEST(AllocationGuard, CatchesADeliberateNew) {
  AllocationGuard guard;
  auto* value = new int(7);
  keep(value);
  delete value;
  EXPECT_EQ(guard.allocations(), 1u);
  EXPECT_EQ(guard.bytes(), sizeof(int));
}

TEST(AllocationGuard, CatchesContainerGrowth) {
  std::vector<double> values;
  AllocationGuard guard;
  values.push_back(1.0);
  keep(values);
  EXPECT_GE(guard.allocations(), 1u);
}

TEST(AllocationGuard, CatchesArrayAndAlignedNew) {
  struct alignas(64) Wide {
    double lanes[8];
  };
  AllocationGuard guard;
  auto array = std::make_unique<char[]>(100);
  auto wide = std::make_unique<Wide>();
  keep(array);
  keep(wide);
  EXPECT_EQ(guard.allocations(), 2u);
}

TEST(AllocationGuard, CatchesTheMallocFamily) {
  AllocationGuard guard;
  void* a = std::malloc(32);
  void* b = std::calloc(4, 8);
  void* c = std::realloc(nullptr, 16);
  keep(a);
  keep(b);
  keep(c);
  std::free(a);
  std::free(b);
  std::free(c);
  EXPECT_EQ(guard.allocations(), 3u);
}

TEST(AllocationGuard, SeesNothingWhenNothingAllocates) {
  std::vector<double> values(16, 1.0);
  AllocationGuard guard;
  double sum = 0.0;
  for (double value : values) sum += value;
  keep(sum);
  EXPECT_EQ(guard.allocations(), 0u);
}

TEST(AllocationGuard, NestedGuardsSeeTheirOwnScope) {
  AllocationGuard outer;
  auto first = std::make_unique<int>(1);
  AllocationGuard inner;
  auto second = std::make_unique<int>(2);
  keep(first);
  keep(second);
  EXPECT_EQ(inner.allocations(), 1u);
  EXPECT_EQ(outer.allocations(), 2u);
}

}  // namespace
}  // namespace nav::testing
