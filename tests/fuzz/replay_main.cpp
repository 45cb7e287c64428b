// Replays inputs through a fuzz target's LLVMFuzzerTestOneInput without libFuzzer, so that
// the seeds and every input the fuzzer kept under tests/data/fuzz/ are regression tests of
// the normal build (any compiler; a sanitizer build reports what the fuzzer would).
// Usage: fuzz_replay_<target> PATH...   (a file, or a folder whose files are replayed in
// name order; a missing folder is skipped). Fails when no input was replayed.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

/// The files named by `argument`: itself, or the regular files of the folder, sorted.
std::vector<fs::path> inputs_of(const fs::path& argument) {
  if (!fs::is_directory(argument))
    return fs::exists(argument) ? std::vector<fs::path>{argument} : std::vector<fs::path>{};
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(argument))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t replayed = 0;
  for (int a = 1; a < argc; ++a) {
    for (const fs::path& file : inputs_of(argv[a])) {
      std::printf("replay %s\n", file.c_str());
      std::fflush(stdout);  // names the input if the target crashes on it
      std::ifstream stream(file, std::ios::binary);
      const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
      LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
      ++replayed;
    }
  }
  std::printf("%zu inputs replayed without a crash\n", replayed);
  return replayed > 0 ? 0 : 1;
}
