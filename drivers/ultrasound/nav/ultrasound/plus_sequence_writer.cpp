#include "nav/ultrasound/plus_sequence_writer.hpp"

#include <zlib.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

namespace nav::ultrasound {
namespace {

std::string frame_prefix(std::size_t index) {
  char prefix[32];
  std::snprintf(prefix, sizeof prefix, "Seq_Frame%04zu_", index);
  return prefix;
}

}  // namespace

std::string format_plus_sequence(const PlusSequence& sequence, bool compress) {
  const std::size_t frames = sequence.frame_pixels() > 0 ? sequence.frames_read : sequence.frame_count;
  std::string pixels(reinterpret_cast<const char*>(sequence.pixels.data()),
                     sequence.frame_pixels() * sequence.frames_read);
  if (compress) {
    uLongf size = compressBound(static_cast<uLong>(pixels.size()));
    std::string packed(size, '\0');
    compress2(reinterpret_cast<Bytef*>(packed.data()), &size, reinterpret_cast<const Bytef*>(pixels.data()),
              static_cast<uLong>(pixels.size()), Z_BEST_SPEED);
    packed.resize(size);
    pixels = std::move(packed);
  }
  std::ostringstream text;
  text.precision(17);
  text << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
       << "CompressedData = " << (compress ? "True" : "False") << '\n';
  if (compress) text << "CompressedDataSize = " << pixels.size() << '\n';
  text << "DimSize = " << sequence.width_px << ' ' << sequence.height_px << ' ' << frames << '\n'
       << "ElementSpacing = " << sequence.spacing_mm[0] << ' ' << sequence.spacing_mm[1] << " 1\n"
       << "ElementType = " << (sequence.frame_pixels() > 0 ? "MET_UCHAR" : "MET_OTHER") << '\n';
  if (!sequence.image_orientation.empty())
    text << "UltrasoundImageOrientation = " << sequence.image_orientation << '\n';
  for (std::size_t i = 0; i < frames; ++i) {
    const std::string prefix = frame_prefix(i);
    for (const TransformTrack& track : sequence.transforms) {
      text << prefix << track.name << "Transform =";
      for (const double value : track.matrices_mm[i]) text << ' ' << value;
      text << '\n' << prefix << track.name << "TransformStatus = " << (track.valid[i] ? "OK" : "INVALID") << '\n';
    }
    text << prefix << "Timestamp = " << sequence.timestamps_s[i] << '\n'
         << prefix << "ImageStatus = " << (sequence.image_valid[i] ? "OK" : "INVALID") << '\n';
  }
  text << "ElementDataFile = LOCAL\n" << pixels;
  return text.str();
}

Status write_plus_sequence(const std::string& path, const PlusSequence& sequence, bool compress) {
  std::ofstream file(path, std::ios::binary);
  const std::string text = format_plus_sequence(sequence, compress);
  file.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!file) return Error{.message = "cannot write", .file = path};
  return Done{};
}

}  // namespace nav::ultrasound
