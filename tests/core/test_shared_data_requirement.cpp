// The tests' rule for the real data of ../shared/data: missing under CI (CI=true) is a
// failure naming the file, so a CI run cannot pass by skipping the real-data cases.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "support/test_data.hpp"

namespace {

/// Sets an environment variable for one test and puts the old value back.
class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value, 1);
  }
  ~ScopedEnvironment() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

void require_a_missing_file() { NAV_REQUIRE_SHARED_DATA("/nonexistent/navrt/liverFine.vtu"); }

void require_a_present_file() { NAV_REQUIRE_SHARED_DATA(nav::testing::test_data_path("mesh/cube.vtk")); }

TEST(SharedDataRequirement, MissingUnderCiIsAFailureNamingTheFile) {
  const ScopedEnvironment ci("CI", "true");
  EXPECT_TRUE(nav::testing::running_under_ci());
  EXPECT_FATAL_FAILURE(require_a_missing_file(), "shared data missing under CI: /nonexistent/navrt/liverFine.vtu");
}

TEST(SharedDataRequirement, PresentDataLetsTheTestGoOnUnderCi) {
  const ScopedEnvironment ci("CI", "true");
  ASSERT_TRUE(nav::testing::file_exists(nav::testing::test_data_path("mesh/cube.vtk")));
  EXPECT_NO_FATAL_FAILURE(require_a_present_file());
}

TEST(SharedDataRequirement, OnlyCiEqualToTrueCounts) {
  const ScopedEnvironment ci("CI", "false");
  EXPECT_FALSE(nav::testing::running_under_ci());
}

}  // namespace
