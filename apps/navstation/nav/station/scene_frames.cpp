#include "nav/station/scene_frames.hpp"

#include "nav/calibration/frame_tree.hpp"

namespace nav::station {

Result<Eigen::Isometry3d> scene_fixed_chain(const Scene& scene, const std::string& target, const std::string& source,
                                            const std::string& hint) {
  const auto urdf_error = [&](const std::string& message) {
    return Error{.message = message, .file = scene.source_path, .line = scene.frames.line, .field = "frames.urdf"};
  };
  auto frames = calibration::FrameTree::load(scene.frames.urdf_path);
  if (!frames.ok()) return urdf_error(frames.error().describe());
  auto chain = frames.value().lookup(target, source, 0);
  if (!chain.ok())
    return urdf_error("no fixed chain from " + target + " to " + source + (hint.empty() ? "" : " (" + hint + ")") +
                      ": " + chain.error().describe());
  return chain.value();
}

}  // namespace nav::station
