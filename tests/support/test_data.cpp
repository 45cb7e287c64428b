#include "support/test_data.hpp"

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace nav::testing {

std::string test_data_path(const std::string& relative) { return std::string(NAV_TEST_DATA_DIR) + "/" + relative; }

std::string shared_data_path(const std::string& relative) {
  return std::string(NAV_SHARED_DATA_DIR) + "/" + relative;
}

bool file_exists(const std::string& path) { return std::ifstream(path).good(); }

std::string temporary_path(const std::string& file_name) {
  const auto folder = std::filesystem::temp_directory_path() / ("navrt-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  return (folder / file_name).string();
}

}  // namespace nav::testing
