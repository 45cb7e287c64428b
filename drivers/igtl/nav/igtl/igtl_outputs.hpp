#pragma once
// The station's outputs as OpenIGTLink messages for 3D Slicer (OpenIGTLinkIF, SlicerIGT), and
// the images a PlusServer sends:
// packed by OpenIGTLink's library, under the device names a SlicerIGT scene looks for, in
// millimetres (the station's metres times 1000) of the station's reference frame.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/dds/samples.hpp"

namespace nav::igtl {

/// The device names of the station's outputs.
inline constexpr const char* kLiverSurfaceDevice = "LiverSurface";       ///< POLYDATA, triangles
inline constexpr const char* kNeedleDevice = "Needle";                   ///< POLYDATA, the centreline
inline constexpr const char* kNeedleTipDevice = "NeedleTipToReference";  ///< TRANSFORM, translation only
inline constexpr const char* kTumourDevice = "Tumour";                   ///< POINT, now and ahead
inline constexpr const char* kHealthDevice = "StationHealth";            ///< STRING
inline constexpr const char* kImageDevice = "Image_Reference";           ///< IMAGE, placed in the reference frame

/// A TRANSFORM named `device`: rotation `orientation_wxyz` and translation `position_m`.
std::vector<std::uint8_t> pack_transform(const std::string& device, const std::array<double, 4>& orientation_wxyz,
                                         const dds::Vector3& position_m, TimeNs time_ns);

/// One named point of a POINT message: where, and its 1-sigma radius.
struct NamedPoint {
  std::string name;
  dds::Vector3 position_m{};
  double radius_m = 0.0;
};
/// A POINT message named `device` holding `points` (OpenIGTLink names of at most 63 characters).
std::vector<std::uint8_t> pack_points(const std::string& device, std::span<const NamedPoint> points, TimeNs time_ns);

/// A POLYDATA named `device`: `vertices_m` and, when `triangles` is empty, one polyline
/// through them in order (a centreline), else those triangles (indices into the vertices).
std::vector<std::uint8_t> pack_polydata(const std::string& device, std::span<const std::array<float, 3>> vertices_m,
                                        std::span<const std::array<std::uint32_t, 3>> triangles, TimeNs time_ns);

/// Where an image lies in the receiver's frame: the rotation of the image's frame (x along a
/// row, y down a column, z their cross product) and the centre of its first pixel.
struct ImagePose {
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  dds::Vector3 first_pixel_m{};
};

/// An IMAGE named `device`: one 8-bit frame of `width_px` x `height_px` pixels (row after row),
/// `spacing_mm` along a row and along a column. Placed at `pose` (OpenIGTLink's matrix holds
/// the image's centre, which Slicer takes back to its first pixel), or, without one, with the
/// identity matrix, as a PlusServer sends a frame not yet placed.
std::vector<std::uint8_t> pack_image(const std::string& device, std::uint32_t width_px, std::uint32_t height_px,
                                     std::span<const std::uint8_t> pixels, const std::array<double, 2>& spacing_mm,
                                     TimeNs time_ns, const ImagePose* pose = nullptr);

/// A STRING message named `device` (US-ASCII).
std::vector<std::uint8_t> pack_string(const std::string& device, const std::string& text, TimeNs time_ns);

}  // namespace nav::igtl
