#pragma once
// Where tests find their input: the project's own small files and the shared real data.
#include <gtest/gtest.h>

#include <string>

namespace nav::testing {

/// Path of a file under tests/data/ (the project's own small test inputs).
std::string test_data_path(const std::string& relative);

/// Path of a file under ../shared/data/ (real data read in place, never copied).
std::string shared_data_path(const std::string& relative);

/// True if the file exists and can be opened.
bool file_exists(const std::string& path);

/// True when the tests run under CI (the environment's CI is "true"), where missing real
/// data is a failure rather than a reason to skip.
bool running_under_ci();

/// The whole text of a file (empty when it cannot be read).
std::string file_text(const std::string& path);

/// The number printed right after `label` in `text`; NaN (failing any bound) and a test
/// failure when `label` is absent.
double number_after(const std::string& text, const std::string& label);

/// A path in this process's own temporary folder for a test's output (the folder goes when
/// the process exits).
std::string temporary_path(const std::string& file_name);

}  // namespace nav::testing

/// Ends the test when the real data at `path` (under ../shared/data) is missing: a failure
/// naming the file under CI, a skip elsewhere.
#define NAV_REQUIRE_SHARED_DATA(path)                                                                                \
  do {                                                                                                               \
    const std::string nav_required_path = (path);                                                                    \
    if (!::nav::testing::file_exists(nav_required_path)) {                                                           \
      if (::nav::testing::running_under_ci()) GTEST_FAIL() << "shared data missing under CI: " << nav_required_path; \
      GTEST_SKIP() << "shared data missing: " << nav_required_path;                                                  \
    }                                                                                                                \
  } while (false)
