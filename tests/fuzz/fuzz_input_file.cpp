#include "fuzz_input_file.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

namespace nav::fuzzing {

const std::string& write_input_file(const std::uint8_t* data, std::size_t size, const std::string& extension) {
  static std::map<std::string, std::string> paths;  // one scratch file per extension
  auto [entry, fresh] = paths.try_emplace(extension);
  if (fresh) {
    const auto name = "navrt-fuzz-" + std::to_string(::getpid()) + "-input" + extension;
    entry->second = (std::filesystem::temp_directory_path() / name).string();
  }
  // A new file each time: rewriting one in place makes ext4 flush it to disk on close.
  std::remove(entry->second.c_str());
  std::FILE* file = std::fopen(entry->second.c_str(), "wb");
  const bool written = file != nullptr && std::fwrite(data, 1, size, file) == size;
  if (file == nullptr || std::fclose(file) != 0 || !written) {
    std::fprintf(stderr, "fuzz: cannot write the scratch file %s\n", entry->second.c_str());
    std::abort();
  }
  return entry->second;
}

}  // namespace nav::fuzzing
