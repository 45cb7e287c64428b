#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace nav::testing {

std::string test_data_path(const std::string& relative) { return std::string(NAV_TEST_DATA_DIR) + "/" + relative; }

std::string shared_data_path(const std::string& relative) { return std::string(NAV_SHARED_DATA_DIR) + "/" + relative; }

bool file_exists(const std::string& path) { return std::ifstream(path).good(); }

bool running_under_ci() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

std::string file_text(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

double number_after(const std::string& text, const std::string& label) {
  const std::size_t at = text.find(label);
  if (at == std::string::npos) {
    ADD_FAILURE() << "missing: " << label;
    return std::nan("");
  }
  return std::strtod(text.c_str() + at + label.size(), nullptr);
}

namespace {

/// This process's scratch folder, removed with what the tests left in it when the process exits.
struct ScratchFolder {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("navrt-test-" + std::to_string(::getpid()));
  ScratchFolder() { std::filesystem::create_directories(path); }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
};

}  // namespace

std::string temporary_path(const std::string& file_name) {
  static const ScratchFolder folder;
  return (folder.path / file_name).string();
}

}  // namespace nav::testing
