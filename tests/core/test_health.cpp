#include "nav/core/health.hpp"

#include <gtest/gtest.h>

#include <string>

namespace nav {

TEST(HealthFlags, RaiseClearAndMerge) {
  HealthFlags flags;
  EXPECT_TRUE(flags.healthy());
  flags.raise(HealthFlag::stale_input);
  flags.raise(HealthFlag::pool_full);
  EXPECT_TRUE(flags.has(HealthFlag::stale_input));
  EXPECT_FALSE(flags.has(HealthFlag::non_finite_state));
  flags.clear(HealthFlag::stale_input);
  EXPECT_FALSE(flags.has(HealthFlag::stale_input));
  HealthFlags other;
  other.raise(HealthFlag::deadline_missed);
  flags.merge(other);
  EXPECT_EQ(flags.bits(), static_cast<std::uint32_t>(HealthFlag::pool_full) |
                              static_cast<std::uint32_t>(HealthFlag::deadline_missed));
  flags.clear_all();
  EXPECT_TRUE(flags.healthy());
}

TEST(HealthFlags, EveryFlagHasADistinctName) {
  EXPECT_EQ(std::string(health_flag_name(HealthFlag::non_finite_state)), "non_finite_state");
  EXPECT_EQ(std::string(health_flag_name(HealthFlag::bad_sample)), "bad_sample");
  EXPECT_EQ(std::string(health_flag_name(HealthFlag::unstable_step)), "unstable_step");
  EXPECT_NE(std::string(health_flag_name(HealthFlag::stale_input)),
            std::string(health_flag_name(HealthFlag::missing_input)));
}

}  // namespace nav
