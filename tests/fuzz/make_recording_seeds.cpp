// Writes the seed corpus of the recording fuzz target into the folder given as argument: a
// recording of one sample per topic closed with its index, and the same recording without
// the index's footer (so that the reader falls back to scanning).
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "dds/dds_test_samples.hpp"
#include "fuzz/seed_generator.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"

namespace {

using namespace nav::dds;

constexpr std::uintmax_t kFooterBytes = 24;  // index offset, record count, "NAVIDX1\n"

/// Appends `sample` encoded to `writer`; false if it did not encode or write.
template <typename Sample>
bool append(RecordingWriter& writer, const Sample& sample, nav::TimeNs time_ns) {
  std::vector<std::uint8_t> bytes;
  return encode_sample(sample, bytes) && writer.append(topic_of<Sample>(), time_ns, time_ns + 1000, bytes).ok();
}

/// Writes one small sample of every topic to `path` and closes it; false on any failure.
bool write_recording(const std::string& path) {
  auto writer = RecordingWriter::create(path);
  if (!writer.ok()) return false;
  RecordingWriter& file = *writer.value();
  return append(file, testing::make_pose(1, 1000), 1000) && append(file, *testing::make_frame(4, 3, 2000), 2000) &&
         append(file, testing::make_needle(3, 3000), 3000) && append(file, testing::make_prediction(4000), 4000) &&
         append(file, *testing::make_surface(2, 5000), 5000) && append(file, testing::make_health(6000), 6000) &&
         file.close().ok();
}

}  // namespace

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  const auto indexed = folder / "indexed.navrec";
  const auto cut = folder / "without_footer.navrec";
  if (!write_recording(indexed.string())) {
    std::fprintf(stderr, "cannot write %s\n", indexed.c_str());
    return false;
  }
  std::filesystem::copy_file(indexed, cut, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::resize_file(cut, std::filesystem::file_size(indexed) - kFooterBytes);
  return true;
}
