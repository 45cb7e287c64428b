#include "nav/igtl/igtl_outputs.hpp"

#include <igtlImageMessage.h>
#include <igtlPointMessage.h>
#include <igtlPolyDataMessage.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>

#include <Eigen/Geometry>
#include <algorithm>

namespace nav::igtl {
namespace {

constexpr double kMmPerM = 1000.0;

/// The seconds and the 2^-32 fraction of `time_ns`, as OpenIGTLink stamps a message.
void stamp(::igtl::MessageBase& message, TimeNs time_ns) {
  const auto seconds = static_cast<unsigned>(time_ns / kNsPerSecond);
  const auto fraction = static_cast<unsigned>(((time_ns % kNsPerSecond) << 32) / kNsPerSecond);
  message.SetTimeStamp(seconds, fraction);
}

Eigen::Matrix3d rotation_of(const std::array<double, 4>& orientation_wxyz) {
  return Eigen::Quaterniond(orientation_wxyz[0], orientation_wxyz[1], orientation_wxyz[2], orientation_wxyz[3])
      .normalized()
      .toRotationMatrix();
}

/// OpenIGTLink's 4x4 of a rotation and a translation in millimetres.
void set_matrix(::igtl::Matrix4x4& matrix, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation_mm) {
  ::igtl::IdentityMatrix(matrix);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) matrix[r][c] = static_cast<float>(rotation(r, c));
    matrix[r][3] = static_cast<float>(translation_mm[r]);
  }
}

std::vector<std::uint8_t> packed(::igtl::MessageBase& message) {
  message.Pack();
  const auto* bytes = static_cast<const std::uint8_t*>(message.GetPackPointer());
  return {bytes, bytes + message.GetPackSize()};
}

}  // namespace

std::vector<std::uint8_t> pack_transform(const std::string& device, const std::array<double, 4>& orientation_wxyz,
                                         const dds::Vector3& position_m, TimeNs time_ns) {
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  message->SetDeviceName(device.c_str());
  ::igtl::Matrix4x4 matrix;
  set_matrix(matrix, rotation_of(orientation_wxyz),
             kMmPerM * Eigen::Vector3d(position_m[0], position_m[1], position_m[2]));
  message->SetMatrix(matrix);
  stamp(*message, time_ns);
  return packed(*message);
}

std::vector<std::uint8_t> pack_points(const std::string& device, std::span<const NamedPoint> points, TimeNs time_ns) {
  ::igtl::PointMessage::Pointer message = ::igtl::PointMessage::New();
  message->SetDeviceName(device.c_str());
  for (const NamedPoint& point : points) {
    ::igtl::PointElement::Pointer element = ::igtl::PointElement::New();
    element->SetName(point.name.substr(0, 63).c_str());
    element->SetPosition(static_cast<float>(kMmPerM * point.position_m[0]),
                         static_cast<float>(kMmPerM * point.position_m[1]),
                         static_cast<float>(kMmPerM * point.position_m[2]));
    element->SetRadius(static_cast<float>(kMmPerM * point.radius_m));
    message->AddPointElement(element);
  }
  stamp(*message, time_ns);
  return packed(*message);
}

std::vector<std::uint8_t> pack_polydata(const std::string& device, std::span<const std::array<float, 3>> vertices_m,
                                        std::span<const std::array<std::uint32_t, 3>> triangles, TimeNs time_ns) {
  ::igtl::PolyDataMessage::Pointer message = ::igtl::PolyDataMessage::New();
  message->SetDeviceName(device.c_str());
  ::igtl::PolyDataPointArray::Pointer points = ::igtl::PolyDataPointArray::New();
  for (const auto& v : vertices_m)
    points->AddPoint(static_cast<float>(kMmPerM * v[0]), static_cast<float>(kMmPerM * v[1]),
                     static_cast<float>(kMmPerM * v[2]));
  message->SetPoints(points);
  ::igtl::PolyDataCellArray::Pointer cells = ::igtl::PolyDataCellArray::New();
  if (triangles.empty()) {
    std::vector<igtlUint32> line(vertices_m.size());
    for (std::size_t i = 0; i < line.size(); ++i) line[i] = static_cast<igtlUint32>(i);
    if (!line.empty()) cells->AddCell(static_cast<int>(line.size()), line.data());
    message->SetLines(cells);
  } else {
    for (const auto& triangle : triangles) {
      igtlUint32 cell[3] = {triangle[0], triangle[1], triangle[2]};
      cells->AddCell(3, cell);
    }
    message->SetPolygons(cells);
  }
  stamp(*message, time_ns);
  return packed(*message);
}

std::vector<std::uint8_t> pack_image(const std::string& device, std::uint32_t width_px, std::uint32_t height_px,
                                     std::span<const std::uint8_t> pixels, const std::array<double, 2>& spacing_mm,
                                     TimeNs time_ns, const ImagePose* pose) {
  ::igtl::ImageMessage::Pointer message = ::igtl::ImageMessage::New();
  message->SetDeviceName(device.c_str());
  message->SetDimensions(static_cast<int>(width_px), static_cast<int>(height_px), 1);
  message->SetSpacing(static_cast<float>(spacing_mm[0]), static_cast<float>(spacing_mm[1]), 1.0f);
  if (pose != nullptr) {
    const Eigen::Matrix3d rotation = rotation_of(pose->orientation_wxyz);
    const Eigen::Vector3d half_extent_mm(0.5 * spacing_mm[0] * (width_px - 1.0),
                                         0.5 * spacing_mm[1] * (height_px - 1.0), 0.0);
    const Eigen::Vector3d first_pixel_mm =
        kMmPerM * Eigen::Vector3d(pose->first_pixel_m[0], pose->first_pixel_m[1], pose->first_pixel_m[2]);
    ::igtl::Matrix4x4 matrix;
    set_matrix(matrix, rotation, first_pixel_mm + rotation * half_extent_mm);
    message->SetMatrix(matrix);
  }
  message->SetScalarTypeToUint8();
  message->AllocateScalars();
  std::copy_n(pixels.begin(), std::min<std::size_t>(pixels.size(), std::size_t{width_px} * height_px),
              static_cast<std::uint8_t*>(message->GetScalarPointer()));
  stamp(*message, time_ns);
  return packed(*message);
}

std::vector<std::uint8_t> pack_string(const std::string& device, const std::string& text, TimeNs time_ns) {
  ::igtl::StringMessage::Pointer message = ::igtl::StringMessage::New();
  message->SetDeviceName(device.c_str());
  message->SetString(text.c_str());
  stamp(*message, time_ns);
  return packed(*message);
}

}  // namespace nav::igtl
