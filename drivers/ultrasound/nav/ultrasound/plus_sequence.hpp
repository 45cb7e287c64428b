#pragma once
// PLUS sequence files (the ecosystem's tracked-ultrasound recordings): a MetaImage (.mha) or
// NRRD (.nrrd) of 8-bit frames whose header carries, per frame, the tracked transforms
// (Seq_FrameNNNN_<From>To<To>Transform, 4x4 row-major, millimetres), their statuses, the
// timestamp (seconds) and the image status. Pixel data raw or zlib/gzip compressed.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "nav/core/error.hpp"

namespace nav::ultrasound {

/// A recorded 4x4 homogeneous transform, row-major, translation in millimetres.
using Matrix4Mm = std::array<double, 16>;

/// One named transform track of a sequence (e.g. "ProbeToTracker"): per frame, the matrix
/// and whether the tracker reported it valid (status OK).
struct TransformTrack {
  std::string name;
  std::vector<Matrix4Mm> matrices_mm;
  std::vector<std::uint8_t> valid;
};

/// A PLUS sequence: frame geometry, per-frame timestamps, statuses and transforms, and the
/// pixels of the frames that were read (frames_read of them, row-major, frame after frame).
struct PlusSequence {
  std::string path;
  std::uint32_t width_px = 0;
  std::uint32_t height_px = 0;
  std::size_t frame_count = 0;  ///< frames listed in the header
  std::array<double, 2> spacing_mm{1.0, 1.0};
  std::string image_orientation;  ///< UltrasoundImageOrientation, e.g. "MFA"
  std::vector<double> timestamps_s;
  std::vector<std::uint8_t> image_valid;
  std::vector<TransformTrack> transforms;
  std::size_t frames_read = 0;
  std::vector<std::uint8_t> pixels;

  std::size_t frame_pixels() const noexcept { return std::size_t{width_px} * height_px; }
  /// The first pixel of frame `index` (< frames_read).
  const std::uint8_t* frame(std::size_t index) const noexcept { return pixels.data() + index * frame_pixels(); }
  /// The track called `name`, or null.
  const TransformTrack* find_transform(std::string_view name) const noexcept;
};

/// What to read: the pixels of at most max_frames frames (0 reads the header only).
struct PlusReadOptions {
  std::size_t max_frames = std::numeric_limits<std::size_t>::max();
};

/// Reads a .mha or .nrrd PLUS sequence file. Errors name the file, the header line and field.
Result<PlusSequence> read_plus_sequence(const std::string& path, const PlusReadOptions& options = {});

/// Parses a sequence held in memory; `name` stands for the file in errors, and its extension
/// (.nrrd or else MetaImage) picks the format.
Result<PlusSequence> parse_plus_sequence(std::string_view bytes, const std::string& name,
                                         const PlusReadOptions& options = {});

}  // namespace nav::ultrasound
