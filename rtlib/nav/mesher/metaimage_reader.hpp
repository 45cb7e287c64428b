#pragma once
// Reads label volumes (segmentations) from MetaImage files, the format ITK and 3D Slicer write.
#include <string>

#include "nav/core/error.hpp"
#include "nav/core/units.hpp"
#include "nav/mesher/label_volume.hpp"

namespace nav {

/// Reads a 3-D label volume from a MetaImage file: a .mha whose voxels follow the header
/// (ElementDataFile = LOCAL) or a .mhd naming a raw file beside it. Supported: NDims = 3,
/// ElementType = MET_UCHAR, uncompressed binary data, no rotation; ElementSpacing and Offset
/// (alias Origin, Position) are in `unit`, millimetres by default as CT spacing is. Errors
/// name the file, the header line and the field.
Result<LabelVolume> read_metaimage_labels(const std::string& path, LengthUnit unit = LengthUnit::millimetre);

}  // namespace nav
