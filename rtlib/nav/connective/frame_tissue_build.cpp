// Init-time construction of a FrameTissueModel and its data.
#include <algorithm>
#include <cmath>
#include <string>

#include "nav/connective/frame_tables.hpp"
#include "nav/connective/frame_tissue_model.hpp"
#include "nav/mesh/geometry.hpp"

namespace nav {
namespace {

using detail::FrameTables;

bool finite_non_negative(double value) { return std::isfinite(value) && value >= 0.0; }

Status check_options(const FrameTissueOptions& options) {
  if (!(std::isfinite(options.step_s) && options.step_s > 0.0))
    return field_error("the step must be a positive number of seconds", "step_s");
  if (options.cg_iterations < 1) return field_error("at least one CG iteration is needed", "cg_iterations");
  if (!finite_non_negative(options.rayleigh_mass_per_s))
    return field_error("damping must be a non-negative number", "rayleigh_mass_per_s");
  if (!finite_non_negative(options.rayleigh_stiffness_s))
    return field_error("damping must be a non-negative number", "rayleigh_stiffness_s");
  if (!(options.cg_residual_bound > 0.0))
    return field_error("the residual bound must be positive", "cg_residual_bound");
  return Done{};
}

/// Pairs, weights and the partition of unity of every point.
Status build_pairs(const FrameLayout& layout, FrameTables& t) {
  const std::size_t points = layout.points_m.size(), frames = layout.frames_m.size();
  if (frames == 0) return field_error("the layout has no frame", "layout.frames_m");
  if (points == 0) return field_error("the layout has no integration point", "layout.points_m");
  if (layout.volumes_m3.size() != points) return field_error("one volume per point is needed", "layout.volumes_m3");
  if (layout.neighbour_offsets.size() != points + 1 || layout.neighbour_offsets.front() != 0)
    return field_error("one offset per point and a final one are needed, starting at 0", "layout.neighbour_offsets");
  const std::size_t pairs = layout.neighbour_frames.size();
  if (static_cast<std::size_t>(layout.neighbour_offsets.back()) != pairs || layout.weights.size() != pairs ||
      layout.weight_gradients_per_m.size() != pairs)
    return field_error("frames, weights and gradients must have one entry per pair", "layout.neighbour_frames");
  for (std::size_t s = 0; s < points; ++s) {
    const std::string point = "point " + std::to_string(s);
    if (!(layout.volumes_m3[s] > 0.0 && std::isfinite(layout.volumes_m3[s])))
      return field_error(point + " has no volume", "layout.volumes_m3");
    if (layout.neighbour_offsets[s + 1] <= layout.neighbour_offsets[s])
      return field_error(point + " has no frame", "layout.neighbour_offsets");
    double sum = 0.0, scale = 0.0;
    Point3 gradient_sum{};
    for (auto k = static_cast<std::size_t>(layout.neighbour_offsets[s]);
         k < static_cast<std::size_t>(layout.neighbour_offsets[s + 1]); ++k) {
      const std::int32_t f = layout.neighbour_frames[k];
      if (f < 0 || static_cast<std::size_t>(f) >= frames)
        return field_error(point + " refers to frame " + std::to_string(f), "layout.neighbour_frames");
      sum += layout.weights[k];
      gradient_sum = gradient_sum + layout.weight_gradients_per_m[k];
      scale = std::max(scale, norm(layout.weight_gradients_per_m[k]));
      for (int a = 0; a < 3; ++a) {
        t.pair_gradient.push_back(layout.weight_gradients_per_m[k][a]);
        t.pair_rest_arm.push_back(layout.points_m[s][a] - layout.frames_m[static_cast<std::size_t>(f)][a]);
      }
      t.pair_frame.push_back(f);
      t.pair_weight.push_back(layout.weights[k]);
    }
    if (!(std::abs(sum - 1.0) < 1e-9)) return field_error(point + ": the weights do not sum to one", "layout.weights");
    if (!(norm(gradient_sum) <= 1e-9 * std::max(scale, 1.0)))
      return field_error(point + ": the weight gradients do not sum to zero", "layout.weight_gradients_per_m");
    t.volume_m3.push_back(layout.volumes_m3[s]);
  }
  t.offsets = layout.neighbour_offsets;
  for (double value : t.pair_rest_arm)
    if (!std::isfinite(value)) return field_error("positions must be finite", "layout.points_m");
  return Done{};
}

/// Lumped masses m_i = sum_s w_is rho v_s and inertias about each frame (each point a small
/// cube of its own volume, so that collinear points still give every axis some inertia).
Status build_masses(const FrameLayout& layout, FrameTables& t) {
  t.mass_kg.assign(static_cast<std::size_t>(t.frame_count), 0.0);
  t.rest_inertia_kg_m2.assign(9 * static_cast<std::size_t>(t.frame_count), 0.0);
  for (std::size_t s = 0; s < layout.points_m.size(); ++s) {
    const double own = std::cbrt(t.volume_m3[s] * t.volume_m3[s]) / 6.0;
    for (auto k = static_cast<std::size_t>(t.offsets[s]); k < static_cast<std::size_t>(t.offsets[s + 1]); ++k) {
      const auto i = static_cast<std::size_t>(t.pair_frame[k]);
      const double m = t.pair_weight[k] * t.density_kg_m3 * t.volume_m3[s];
      t.mass_kg[i] += m;
      const double* arm = &t.pair_rest_arm[3 * k];
      const double arm2 = arm[0] * arm[0] + arm[1] * arm[1] + arm[2] * arm[2];
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
          t.rest_inertia_kg_m2[9 * i + 3 * c + r] += m * ((r == c ? arm2 + own : 0.0) - arm[r] * arm[c]);
    }
  }
  for (std::size_t i = 0; i < t.mass_kg.size(); ++i)
    if (!(t.mass_kg[i] > 0.0))
      return field_error("frame " + std::to_string(i) + " carries no integration point", "layout.frames_m");
  return Done{};
}

Status build_supports(const FrameSupports& supports, FrameTables& t) {
  const auto n = static_cast<std::size_t>(t.frame_count);
  t.constrained.assign(6 * n, 0);
  std::vector<int> kind(n, 0);
  for (std::int32_t f : supports.fixed_frames) {
    if (f < 0 || static_cast<std::size_t>(f) >= n)
      return field_error("frame " + std::to_string(f) + " is out of range", "supports.fixed_frames");
    if (kind[static_cast<std::size_t>(f)] != 0)
      return field_error("frame " + std::to_string(f) + " is listed twice", "supports.fixed_frames");
    kind[static_cast<std::size_t>(f)] = 1;
    std::fill_n(t.constrained.begin() + 6 * f, 6, 1);
  }
  if (!supports.driven_axes.empty() && supports.driven_axes.size() != supports.driven_frames.size())
    return field_error("one axis mask per driven frame, or none", "supports.driven_axes");
  for (std::size_t d = 0; d < supports.driven_frames.size(); ++d) {
    const std::int32_t f = supports.driven_frames[d];
    if (f < 0 || static_cast<std::size_t>(f) >= n)
      return field_error("frame " + std::to_string(f) + " is out of range", "supports.driven_frames");
    if (kind[static_cast<std::size_t>(f)] != 0)
      return field_error("frame " + std::to_string(f) + " is fixed or driven twice", "supports.driven_frames");
    kind[static_cast<std::size_t>(f)] = 2;
    const std::array<bool, 3> axes =
        supports.driven_axes.empty() ? std::array<bool, 3>{true, true, true} : supports.driven_axes[d];
    for (int a = 0; a < 3; ++a) t.constrained[6 * static_cast<std::size_t>(f) + a] = axes[a] ? 1 : 0;
    for (int a = 3; a < 6; ++a)
      t.constrained[6 * static_cast<std::size_t>(f) + a] = supports.hold_driven_rotations ? 1 : 0;
    t.driven_axes.push_back(axes);
  }
  t.fixed_frames = supports.fixed_frames;
  t.driven_frames = supports.driven_frames;
  t.hold_driven_rotations = supports.hold_driven_rotations;
  if (std::count(t.constrained.begin(), t.constrained.end(), 0) == 0)
    return field_error("every DOF is held", "supports");
  return Done{};
}

/// Half-bandwidth (DOFs) of the system in the frame numbering.
Status build_band(FrameTables& t) {
  if (t.options.solver != FrameSolver::banded_cholesky) return Done{};
  std::int64_t frames_apart = 0;
  for (std::size_t s = 0; s + 1 < t.offsets.size(); ++s) {
    const auto first = t.pair_frame.begin() + t.offsets[s], last = t.pair_frame.begin() + t.offsets[s + 1];
    frames_apart =
        std::max<std::int64_t>(frames_apart, *std::max_element(first, last) - *std::min_element(first, last));
  }
  t.half_bandwidth = 6 * frames_apart + 5;
  if (6 * t.frame_count * (t.half_bandwidth + 1) > t.options.max_band_entries)
    return field_error("the band of " + std::to_string(6 * t.frame_count) + " DOFs and half-bandwidth " +
                           std::to_string(t.half_bandwidth) +
                           " exceeds max_band_entries: number the frames along the short axes first, or use CG",
                       "solver");
  return Done{};
}

}  // namespace

Result<FrameTissueModel> make_frame_tissue_model(const FrameTissueScene& scene, const FrameTissueOptions& options) {
  if (auto s = check_options(options); !s) return s.error();
  if (auto s = check_material(scene.material, "material"); !s) return s.error();
  for (double g : scene.gravity_m_s2)
    if (!std::isfinite(g)) return field_error("gravity must be finite", "gravity_m_s2");
  auto tables = std::make_shared<FrameTables>();
  FrameTables& t = *tables;
  t.options = options;
  t.frame_count = static_cast<std::int64_t>(scene.layout.frames_m.size());
  t.point_count = static_cast<std::int64_t>(scene.layout.points_m.size());
  t.lame = lame_parameters(scene.material);
  t.density_kg_m3 = scene.material.density_kg_m3;
  t.gravity_m_s2 = scene.gravity_m_s2;
  t.max_frame_forces = scene.max_frame_forces;
  for (const Point3& p : scene.layout.frames_m) {
    for (double c : p)
      if (!std::isfinite(c)) return field_error("frame positions must be finite", "layout.frames_m");
    t.rest_m.insert(t.rest_m.end(), p.begin(), p.end());
  }
  if (auto s = build_pairs(scene.layout, t); !s) return s.error();
  if (auto s = build_masses(scene.layout, t); !s) return s.error();
  if (auto s = build_supports(scene.supports, t); !s) return s.error();
  if (auto s = build_band(t); !s) return s.error();
  return FrameTissueModel(std::move(tables));
}

Result<FrameTissueData> make_frame_tissue_data(const FrameTissueModel& model) {
  const FrameTables& t = model.tables();
  const auto n = static_cast<std::size_t>(t.frame_count), points = static_cast<std::size_t>(t.point_count);
  const std::size_t pairs = t.pair_frame.size(), driven = t.driven_frames.size();
  const std::size_t band =
      t.options.solver == FrameSolver::banded_cholesky ? 6 * n * static_cast<std::size_t>(t.half_bandwidth + 1) : 0;
  const std::size_t sizes[] = {3 * n,  4 * n,  6 * n, 3 * driven, 9 * n,      9 * n,     6 * n,
                               6 * n,  6 * n,  6 * n, 6 * n,      6 * n,      6 * n,     6 * n,
                               13 * n, 36 * n, band,  9 * points, 9 * points, 3 * pairs, 9 * n};
  ArenaPlan plan;
  for (std::size_t size : sizes) plan.add<double>(size);
  FrameTissueData data(Arena("frame_tissue_data", plan.bytes()));
  std::span<double>* spans[] = {&data.positions_m, &data.orientations_wxyz, &data.velocities,     &data.driven_forces_n,
                                &data.rotations,   &data.inertias,          &data.forces,         &data.rhs,
                                &data.solution,    &data.residual,          &data.preconditioned, &data.direction,
                                &data.product,     &data.free_velocities,   &data.backup,         &data.blocks,
                                &data.band,        &data.point_gradients,   &data.point_stresses, &data.pair_arms,
                                &data.frame_spins};
  for (std::size_t k = 0; k < std::size(sizes); ++k) {
    auto carved = data.arena.allocate<double>("frame tissue buffer", sizes[k]);
    if (!carved.ok()) return carved.error();
    *spans[k] = carved.value();
  }
  std::copy(t.rest_m.begin(), t.rest_m.end(), data.positions_m.begin());
  for (std::size_t i = 0; i < n; ++i) data.orientations_wxyz[4 * i] = 1.0;
  return data;
}

std::int64_t FrameTissueModel::frame_count() const { return tables_->frame_count; }
std::int64_t FrameTissueModel::point_count() const { return tables_->point_count; }
std::int64_t FrameTissueModel::pair_count() const { return static_cast<std::int64_t>(tables_->pair_frame.size()); }
const FrameTissueOptions& FrameTissueModel::options() const { return tables_->options; }
std::span<const double> FrameTissueModel::rest_positions_m() const { return tables_->rest_m; }
std::span<const double> FrameTissueModel::frame_masses_kg() const { return tables_->mass_kg; }
std::span<const std::int32_t> FrameTissueModel::driven_frames() const { return tables_->driven_frames; }
std::int64_t FrameTissueModel::half_bandwidth() const { return tables_->half_bandwidth; }

}  // namespace nav
