#pragma once
// The immutable tables of a FrameTissueModel: frames, frame-point pairs with their weights,
// gradients and rest arms, masses, supports. Internal to the connective tissue's .cpp files.
#include <array>
#include <cstdint>
#include <vector>

#include "nav/connective/frame_tissue_model.hpp"

namespace nav::detail {

struct FrameTables {
  FrameTissueOptions options;
  std::int64_t frame_count = 0;
  std::int64_t point_count = 0;
  std::vector<double> rest_m;              ///< 3 per frame
  std::vector<double> mass_kg;             ///< per frame
  std::vector<double> rest_inertia_kg_m2;  ///< 9 per frame, about the frame's origin, rest axes
  std::vector<std::int32_t> offsets;       ///< point s owns pairs [offsets[s], offsets[s+1])
  std::vector<std::int32_t> pair_frame;
  std::vector<double> pair_weight;
  std::vector<double> pair_gradient;  ///< 3 per pair, per metre
  std::vector<double> pair_rest_arm;  ///< 3 per pair: rest point minus rest frame
  std::vector<double> volume_m3;      ///< per point
  LameParameters lame;
  double density_kg_m3 = 0.0;
  Point3 gravity_m_s2{};
  std::vector<std::uint8_t> constrained;  ///< 6 per frame: 1 where the DOF is not solved for
  std::vector<std::int32_t> fixed_frames;
  std::vector<std::int32_t> driven_frames;
  std::vector<std::array<bool, 3>> driven_axes;
  bool hold_driven_rotations = false;
  std::size_t max_frame_forces = 16;
  std::int64_t half_bandwidth = 0;  ///< in DOFs, banded_cholesky only
};

}  // namespace nav::detail
