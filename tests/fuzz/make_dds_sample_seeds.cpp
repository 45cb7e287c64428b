// Writes the seed corpus of the dds_sample fuzz target into the folder given as argument: for
// every topic type (the first byte), a sample as a writer encodes it, the same bytes under
// every other RTPS encapsulation identifier 0x0000-0x000b and with a first byte of 0x01 (the
// payloads that once ended a station inside the generated decoder), and cut in half.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "dds/dds_test_samples.hpp"
#include "fuzz/seed_generator.hpp"
#include "nav/dds/sample_codec.hpp"

namespace {

using namespace nav::dds;

bool write_seed(const std::filesystem::path& path, std::uint8_t topic, const std::vector<std::uint8_t>& payload,
                std::size_t size) {
  std::ofstream file(path, std::ios::binary);
  file.put(static_cast<char>(topic));
  file.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(size));
  if (!file) std::fprintf(stderr, "cannot write %s\n", path.c_str());
  return static_cast<bool>(file);
}

/// The seeds of one sample: its encoding, its other encapsulations and its first half.
template <typename Sample>
bool write_seeds(const std::filesystem::path& folder, const Sample& sample) {
  const auto topic = static_cast<std::uint8_t>(topic_of<Sample>());
  std::vector<std::uint8_t> bytes;
  if (!encode_sample(sample, bytes)) return false;
  const std::string stem = "topic" + std::to_string(topic);
  bool written = write_seed(folder / (stem + "_half"), topic, bytes, bytes.size() / 2);
  for (std::uint8_t id = 0; id <= 0x0b; ++id) {
    bytes[1] = id;
    written =
        write_seed(folder / (stem + "_encapsulation" + std::to_string(id)), topic, bytes, bytes.size()) && written;
  }
  bytes[0] = 0x01;
  return write_seed(folder / (stem + "_first_byte_1"), topic, bytes, bytes.size()) && written;
}

}  // namespace

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  using namespace nav::dds::testing;
  return write_seeds(folder, make_pose(1, 1000)) && write_seeds(folder, *make_frame(4, 3, 2000)) &&
         write_seeds(folder, make_needle(3, 3000)) && write_seeds(folder, make_prediction(4000)) &&
         write_seeds(folder, *make_surface(2, 5000)) && write_seeds(folder, make_health(6000)) &&
         write_seeds(folder, make_truth(7000));
}
