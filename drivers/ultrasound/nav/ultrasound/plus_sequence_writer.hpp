#pragma once
// Writes PLUS sequence files (.mha), so that simulated sessions can be replayed by any tool of
// the ecosystem and the reader's tests and fuzz seeds have small inputs of known content.
#include <string>

#include "nav/core/error.hpp"
#include "nav/ultrasound/plus_sequence.hpp"

namespace nav::ultrasound {

/// The MetaImage text of `sequence` (header and its frames_read frames, zlib-compressed when
/// `compress`); frame_count is taken as frames_read when pixels are given.
std::string format_plus_sequence(const PlusSequence& sequence, bool compress);

/// Writes format_plus_sequence to `path`.
Status write_plus_sequence(const std::string& path, const PlusSequence& sequence, bool compress);

}  // namespace nav::ultrasound
