#pragma once
// The scene's fixed frames: the chains of its URDF (frames.urdf) that the station builds from.
#include <string>

#include <Eigen/Geometry>

#include "nav/core/error.hpp"
#include "nav/station/scene.hpp"

namespace nav::station {

/// target_from_source along the fixed joints of the scene's URDF; an error at the scene's
/// frames.urdf when the file does not load or no fixed chain joins the two frames (`hint`,
/// when given, says where such a chain comes from).
Result<Eigen::Isometry3d> scene_fixed_chain(const Scene& scene, const std::string& target, const std::string& source,
                                            const std::string& hint = "");

}  // namespace nav::station
