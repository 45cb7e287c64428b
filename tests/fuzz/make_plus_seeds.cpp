// Writes the seed corpus of the PLUS sequence fuzz target into the folder given as argument:
// small synthetic sequences (never the real recordings): raw and zlib-compressed MetaImage
// with two tracked 4 x 3 frames, a tracker-only buffer, and a raw NRRD.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz/seed_generator.hpp"
#include "nav/ultrasound/plus_sequence_writer.hpp"

namespace {

nav::ultrasound::PlusSequence two_frames(std::uint32_t width_px, std::uint32_t height_px) {
  nav::ultrasound::PlusSequence sequence;
  sequence.width_px = width_px;
  sequence.height_px = height_px;
  sequence.frame_count = 2;
  sequence.frames_read = width_px * height_px > 0 ? 2 : 0;
  sequence.spacing_mm = {0.2, 0.25};
  sequence.image_orientation = "MF";
  sequence.timestamps_s = {10.0, 10.05};
  sequence.image_valid = {1, 0};
  for (std::size_t i = 0; i < sequence.frame_pixels() * sequence.frames_read; ++i) {
    sequence.pixels.push_back(static_cast<std::uint8_t>(i * 37));
  }
  nav::ultrasound::TransformTrack probe;
  probe.name = "ProbeToTracker";
  probe.matrices_mm = {{1, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, 30, 0, 0, 0, 1},
                       {0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1}};
  probe.valid = {1, 0};
  sequence.transforms.push_back(probe);
  return sequence;
}

bool write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary);
  file << text;
  return static_cast<bool>(file);
}

}  // namespace

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  const auto frames = two_frames(4, 3);
  const std::string nrrd =
      "NRRD0004\n# a raw NRRD sequence\ndimension: 3\nencoding: raw\nsizes: 2 2 1\ntype: uint8\n"
      "ultrasound image orientation:=MF\nSeq_Frame0000_ProbeToTrackerTransform:=1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
      "Seq_Frame0000_ProbeToTrackerTransformStatus:=OK\nSeq_Frame0000_Timestamp:=1.25\nSeq_Frame0000_Status:="
      "OK\n\nabcd";
  const bool ok =
      write_text(folder / "raw.mha", nav::ultrasound::format_plus_sequence(frames, false)) &&
      write_text(folder / "compressed.mha", nav::ultrasound::format_plus_sequence(frames, true)) &&
      write_text(folder / "tracker_only.mha", nav::ultrasound::format_plus_sequence(two_frames(0, 0), false)) &&
      write_text(folder / "raw.nrrd", nrrd);
  if (!ok) {
    std::fprintf(stderr, "cannot write the seeds into %s\n", folder.c_str());
    return false;
  }
  return true;
}
