#pragma once
// The station's outputs as the OpenIGTLink messages displays read (nav/igtl/igtl_outputs.hpp
// names them): the deformed liver surface with the triangles of the scene's mesh, the needle's
// centreline and tip, the tumour now and ahead with its uncertainty, the health in words, the
// ultrasound frame where it lies. Each packed with a wall-clock stamp.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"
#include "nav/fusion/rigid_pose.hpp"

namespace nav::bridge {

/// A packed message.
using Packed = std::vector<std::uint8_t>;

/// Packs station samples; knows the surface's triangles (the station's display surface).
class OutboundPacker {
 public:
  /// `triangles` index the surface's `vertex_count` vertices.
  OutboundPacker(std::vector<std::array<std::uint32_t, 3>> triangles, std::uint32_t vertex_count)
      : triangles_(std::move(triangles)), vertex_count_(vertex_count) {}

  /// LiverSurface; an Error when the sample's vertices are not the scene's surface's.
  Result<Packed> surface(const dds::DeformedSurface& surface, TimeNs wall_ns) const;
  /// Needle (the centreline) and NeedleTipToReference (its last point); nothing without points.
  std::vector<Packed> needle(const dds::NeedleState& needle, TimeNs wall_ns) const;
  /// Tumour: the points "now" and "ahead" (when known), each with its 1-sigma radius
  /// (station::sigma_radius_m).
  Packed tumour(const dds::TargetPrediction* now, const dds::TargetPrediction* ahead, TimeNs wall_ns) const;
  /// StationHealth: dds::health_summary's line.
  Packed health(const dds::StationHealth& health, TimeNs wall_ns) const;
  /// Image_Reference: the ultrasound frame placed at `model_from_image` (its first pixel at the origin).
  Packed image(const dds::UltrasoundFrame& frame, const RigidPose& model_from_image, TimeNs wall_ns) const;

 private:
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::uint32_t vertex_count_;
};

}  // namespace nav::bridge
