#pragma once
// Shared inputs of the connective-tissue tests: grids and models of blocks and beams, frames
// selected by position, rotations of frames, a hash of a state for repeatability checks, and
// the two ligaments that hang the embedded liver.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/connective/frame_tissue_model.hpp"
#include "nav/connective/organ_ligaments.hpp"
#include "support/bits_hash.hpp"

namespace nav::testing {

/// A grid of counts frames spaced `spacing_m`, from the origin along x, y, z.
inline FrameGrid block_grid(std::array<int, 3> counts, std::array<double, 3> spacing_m) {
  FrameGrid grid;
  grid.counts = counts;
  grid.spacing_m = spacing_m;
  return grid;
}

/// Frames of `layout` whose rest coordinate `axis` equals value_m (to 1 nm).
inline std::vector<std::int32_t> frames_where(const FrameLayout& layout, int axis, double value_m) {
  std::vector<std::int32_t> frames;
  for (std::size_t f = 0; f < layout.frames_m.size(); ++f)
    if (std::abs(layout.frames_m[f][axis] - value_m) < 1e-9) frames.push_back(static_cast<std::int32_t>(f));
  return frames;
}

/// The scene of `layout` with the given material and supports.
inline FrameTissueScene scene_of(const FrameLayout& layout, const ElasticMaterial& material,
                                 FrameSupports supports = {}, Point3 gravity_m_s2 = {0.0, 0.0, 0.0}) {
  FrameTissueScene scene;
  scene.layout = layout;
  scene.material = material;
  scene.supports = std::move(supports);
  scene.gravity_m_s2 = gravity_m_s2;
  return scene;
}

/// Turns frame `frame` by the rotation vector `turn_rad` (on the left, as the step does).
inline void turn_frame(FrameTissueData& data, std::size_t frame, const Eigen::Vector3d& turn_rad) {
  const double angle = turn_rad.norm();
  if (angle == 0.0) return;
  const Eigen::Quaterniond dq(Eigen::AngleAxisd(angle, turn_rad / angle));
  double* q = data.orientations_wxyz.data() + 4 * frame;
  const Eigen::Quaterniond turned = (dq * Eigen::Quaterniond(q[0], q[1], q[2], q[3])).normalized();
  q[0] = turned.w();
  q[1] = turned.x();
  q[2] = turned.y();
  q[3] = turned.z();
}

/// Moves DOF k (6 per frame: translation, rotation increment) by `delta`.
inline void move_dof(FrameTissueData& data, std::size_t k, double delta) {
  const std::size_t frame = k / 6, a = k % 6;
  if (a < 3) {
    data.positions_m[3 * frame + a] += delta;
  } else {
    turn_frame(data, frame, delta * Eigen::Vector3d::Unit(static_cast<int>(a - 3)));
  }
}

/// Two 3 x 3 cm ligaments, 3 cm long, over the embedded liver's right lobe and the left of
/// its falciform plane.
inline std::vector<LigamentSpec> two_ligaments() {
  std::vector<LigamentSpec> specs(2);
  specs[0].footprint_centre_m = {-0.045, 0.0, 0.0};
  specs[1].footprint_centre_m = {0.035, 0.015, 0.0};
  for (LigamentSpec& spec : specs) spec.embed_m = 0.006;
  return specs;
}

}  // namespace nav::testing
