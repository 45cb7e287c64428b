#include "nav/needle/needle_lane_kernels.hpp"
#include "nav/needle/needle_model.hpp"

#include <algorithm>
#include <cmath>

namespace nav {

double NeedleModel::node_mass_kg(int node) const {
  return end_and_inner_mass_kg[node == 0 || node == element_count ? 0 : 1];
}

double NeedleModel::node_rotary_inertia_kg_m2(int node) const {
  return end_and_inner_rotary_inertia_kg_m2[node == 0 || node == element_count ? 0 : 1];
}

Result<NeedleModel> make_needle_model(const NeedleParameters& parameters) {
  if (auto valid = validate_needle_parameters(parameters); !valid) return valid.error();
  NeedleModel model;
  model.parameters = parameters;
  model.section = needle_section(parameters);
  model.element_count = parameters.element_count;
  model.element_length_m = parameters.length_m / parameters.element_count;
  model.local_stiffness = beam_stiffness(beam_local_stiffness(parameters, model.section, model.element_length_m));
  const double element_mass_kg = parameters.density_kg_m3 * model.section.area_m2 * model.element_length_m;
  const double element_inertia = parameters.density_kg_m3 * model.section.polar_moment_m4 * model.element_length_m;
  model.end_and_inner_mass_kg = {0.5 * element_mass_kg, element_mass_kg};
  model.end_and_inner_rotary_inertia_kg_m2 = {0.5 * element_inertia, element_inertia};
  return model;
}

Result<NeedleData> make_needle_data(const NeedleModel& model, const NeedlePose& base) {
  for (double v : base.position_m)
    if (!std::isfinite(v)) return Error{.message = "must be finite", .field = "needle.base.position_m"};
  double norm2 = 0.0;
  for (double v : base.rotation_wxyz) norm2 += v * v;
  if (!std::isfinite(norm2) || std::abs(norm2 - 1.0) > 1e-6)
    return Error{.message = "must be a unit quaternion", .field = "needle.base.rotation_wxyz"};
  const auto nodes = static_cast<std::size_t>(model.node_count());
  const auto free_blocks = nodes - 1;
  ArenaPlan plan;
  plan.add<double>(3 * nodes).add<double>(4 * nodes).add<double>(3 * nodes).add<double>(3 * nodes);
  plan.add<double>(3 * nodes).add<double>(4 * nodes).add<double>(3 * nodes).add<double>(3 * nodes);
  plan.add<double>(6 * nodes).add<double>(6 * nodes);
  for (int k = 0; k < 5; ++k) plan.add<double>(36 * free_blocks);
  const std::size_t stride =
      (3 * free_blocks + detail::kCombinedLanes - 1) / detail::kCombinedLanes * detail::kCombinedLanes;
  const std::size_t translational = 3 * free_blocks * stride + detail::kCombinedLanes;
  plan.add<double>(18 * free_blocks).add<double>(translational);
  NeedleData data(Arena("needle_data", plan.bytes()));
  struct Buffer {
    std::span<double>* span;
    std::size_t count;
    const char* what;
  };
  const Buffer buffers[] = {
      {&data.positions_m, 3 * nodes, "positions"},
      {&data.rotations_wxyz, 4 * nodes, "rotations"},
      {&data.velocities_m_s, 3 * nodes, "velocities"},
      {&data.angular_velocities_rad_s, 3 * nodes, "angular velocities"},
      {&data.start_positions_m, 3 * nodes, "start positions"},
      {&data.start_rotations_wxyz, 4 * nodes, "start rotations"},
      {&data.start_velocities_m_s, 3 * nodes, "start velocities"},
      {&data.start_angular_velocities_rad_s, 3 * nodes, "start angular velocities"},
      {&data.forces, 6 * nodes, "forces"},
      {&data.residual, 6 * nodes, "residual"},
      {&data.system.diagonal, 36 * free_blocks, "diagonal blocks"},
      {&data.system.upper, 36 * free_blocks, "upper blocks"},
      {&data.system.schur, 36 * free_blocks, "schur factors"},
      {&data.system.multiplier, 36 * free_blocks, "multipliers"},
      {&data.inverse_diagonal, 36 * free_blocks, "inverse diagonal"},
      {&data.inverse_column, 18 * free_blocks, "inverse column"},
      {&data.translational_compliance, translational, "translational compliance"},
  };
  for (const Buffer& b : buffers) {
    auto carved = data.arena.allocate<double>(b.what, b.count);
    if (!carved.ok()) return carved.error();
    *b.span = carved.value();
  }
  data.system.blocks = static_cast<int>(free_blocks);
  data.translational_stride = stride;
  place_straight_needle(model, data, base);
  return data;
}

bool is_finite_unit_pose(const NeedlePose& base) noexcept {
  double norm2 = 0.0;
  for (double v : base.rotation_wxyz) norm2 += v * v;
  bool finite = std::isfinite(norm2) && std::abs(norm2 - 1.0) <= 1e-6;
  for (double v : base.position_m) finite = finite && std::isfinite(v);
  return finite;
}

void place_straight_needle(const NeedleModel& model, NeedleData& data, const NeedlePose& base) noexcept {
  const Eigen::Quaterniond q(base.rotation_wxyz[0], base.rotation_wxyz[1], base.rotation_wxyz[2],
                             base.rotation_wxyz[3]);
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitX();
  for (std::size_t n = 0; n < static_cast<std::size_t>(model.node_count()); ++n) {
    for (int c = 0; c < 3; ++c)
      data.positions_m[3 * n + static_cast<std::size_t>(c)] =
          base.position_m[static_cast<std::size_t>(c)] + static_cast<double>(n) * model.element_length_m * axis[c];
    for (std::size_t c = 0; c < 4; ++c) data.rotations_wxyz[4 * n + c] = base.rotation_wxyz[c];
  }
  std::fill(data.velocities_m_s.begin(), data.velocities_m_s.end(), 0.0);
  std::fill(data.angular_velocities_rad_s.begin(), data.angular_velocities_rad_s.end(), 0.0);
}

}  // namespace nav
