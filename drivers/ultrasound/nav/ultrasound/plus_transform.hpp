#pragma once
// A recorded PLUS transform (4x4 row-major, millimetres) as a rigid transform in metres.
#include <Eigen/Geometry>

#include "nav/ultrasound/plus_sequence.hpp"

namespace nav::ultrasound {

/// The rigid transform of `matrix_mm`: the nearest rotation to its 3x3 block (recordings
/// carry rounding) and its translation in metres.
Eigen::Isometry3d rigid_transform_m(const Matrix4Mm& matrix_mm);

}  // namespace nav::ultrasound
