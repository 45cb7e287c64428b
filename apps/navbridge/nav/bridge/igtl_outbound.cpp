#include "nav/bridge/igtl_outbound.hpp"

#include <string>

#include "nav/dds/health_text.hpp"
#include "nav/igtl/igtl_outputs.hpp"
#include "nav/station/target_sigma.hpp"

namespace nav::bridge {

Result<Packed> OutboundPacker::surface(const dds::DeformedSurface& surface, TimeNs wall_ns) const {
  if (surface.vertex_count != vertex_count_)
    return Error{.message = "a surface of " + std::to_string(surface.vertex_count) +
                            " vertices where the scene's liver surface has " + std::to_string(vertex_count_) +
                            " (the station runs another scene)",
                 .field = "vertex_count"};
  return igtl::pack_polydata(igtl::kLiverSurfaceDevice, {surface.vertex_positions_m.data(), surface.vertex_count},
                             triangles_, wall_ns);
}

std::vector<Packed> OutboundPacker::needle(const dds::NeedleState& needle, TimeNs wall_ns) const {
  if (needle.point_count == 0) return {};
  std::vector<std::array<float, 3>> points(needle.point_count);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) points[i][k] = static_cast<float>(needle.shape_points_m[i][k]);
  std::vector<Packed> packed;
  packed.push_back(igtl::pack_polydata(igtl::kNeedleDevice, points, {}, wall_ns));
  packed.push_back(igtl::pack_transform(igtl::kNeedleTipDevice, {1.0, 0.0, 0.0, 0.0},
                                        needle.shape_points_m[needle.point_count - 1], wall_ns));
  return packed;
}

Packed OutboundPacker::tumour(const dds::TargetPrediction* now, const dds::TargetPrediction* ahead,
                              TimeNs wall_ns) const {
  std::vector<igtl::NamedPoint> points;
  if (now != nullptr) points.push_back({"now", now->position_m, station::sigma_radius_m(now->covariance_m2)});
  if (ahead != nullptr) points.push_back({"ahead", ahead->position_m, station::sigma_radius_m(ahead->covariance_m2)});
  return igtl::pack_points(igtl::kTumourDevice, points, wall_ns);
}

Packed OutboundPacker::health(const dds::StationHealth& health, TimeNs wall_ns) const {
  return igtl::pack_string(igtl::kHealthDevice, dds::health_summary(health), wall_ns);
}

Packed OutboundPacker::image(const dds::UltrasoundFrame& frame, const RigidPose& model_from_image,
                             TimeNs wall_ns) const {
  const Eigen::Quaterniond& q = model_from_image.rotation;
  const Eigen::Vector3d& p = model_from_image.position_m;
  const igtl::ImagePose pose{{q.w(), q.x(), q.y(), q.z()}, {p.x(), p.y(), p.z()}};
  return igtl::pack_image(igtl::kImageDevice, frame.width_px, frame.height_px,
                          {frame.pixels.data(), frame.pixel_count()},
                          {1e3 * frame.pixel_spacing_m[0], 1e3 * frame.pixel_spacing_m[1]}, wall_ns, &pose);
}

}  // namespace nav::bridge
