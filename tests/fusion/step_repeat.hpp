#pragma once
// The step-function check shared by the fusion tests: a scripted run, done twice, allocates
// nothing inside its guarded steps and gives bitwise-identical outputs.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <vector>

namespace nav::testing {

/// Calls `run(&allocations)` twice (it returns every output as doubles and counts the
/// allocations of its guarded steps); expects zero allocations and equal bits. Returns the
/// first run's outputs for further checks.
template <typename Run>
std::vector<double> expect_allocation_free_and_repeatable(Run run) {
  std::size_t first_allocations = 1;
  std::size_t second_allocations = 1;
  const std::vector<double> first = run(&first_allocations);
  const std::vector<double> second = run(&second_allocations);
  EXPECT_EQ(first_allocations, 0u);
  EXPECT_EQ(second_allocations, 0u);
  EXPECT_EQ(first.size(), second.size());
  if (first.size() == second.size()) {
    EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(double)), 0);
  }
  return first;
}

}  // namespace nav::testing
