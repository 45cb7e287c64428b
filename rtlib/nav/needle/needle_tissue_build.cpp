#include <cmath>
#include <numbers>
#include <string>

#include "nav/needle/gauss_seidel.hpp"
#include "nav/needle/needle_tissue_model.hpp"
#include "nav/needle/tissue_points.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {

namespace {

Error scene_error(const std::string& field, const char* message) {
  return Error{.message = message, .field = "scene." + field};
}

bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

Status validate_scene(const NeedleTissueScene& s) {
  for (std::size_t l = 0; l < s.layers.size(); ++l) {
    const TissueLayer& layer = s.layers[l];
    const std::string at = "layers[" + std::to_string(l) + "].";
    const double n2 = layer.outward_normal[0] * layer.outward_normal[0] +
                      layer.outward_normal[1] * layer.outward_normal[1] +
                      layer.outward_normal[2] * layer.outward_normal[2];
    if (!(std::abs(n2 - 1.0) < 1e-9)) return scene_error(at + "outward_normal", "must be a unit vector");
    for (double v : layer.surface_point_m)
      if (!std::isfinite(v)) return scene_error(at + "surface_point_m", "must be finite");
    if (layer.surface < -1 || layer.surface >= static_cast<std::int32_t>(s.surfaces.size()))
      return scene_error(at + "surface", "must name one of the scene's surfaces (or be -1: the plane)");
    if (!positive(layer.puncture_force_n)) return scene_error(at + "puncture_force_n", "must be positive");
    if (!non_negative(layer.cutting_force_n)) return scene_error(at + "cutting_force_n", "must be finite and >= 0");
    if (!non_negative(layer.friction_per_length_n_m))
      return scene_error(at + "friction_per_length_n_m", "must be finite and >= 0");
    if (!non_negative(layer.surface_friction_coefficient))
      return scene_error(at + "surface_friction_coefficient", "must be finite and >= 0");
  }
  if (s.layers.size() > 16) return scene_error("layers", "at most 16 layers");
  if (!non_negative(s.surface_reach_margin_m)) return scene_error("surface_reach_margin_m", "must be finite and >= 0");
  if (!positive(s.point_compliance_m_per_n)) return scene_error("point_compliance_m_per_n", "must be positive");
  if (!positive(s.compliance_correlation_length_m))
    return scene_error("compliance_correlation_length_m", "must be positive");
  if (!non_negative(s.shaft_friction_coefficient))
    return scene_error("shaft_friction_coefficient", "must be finite and >= 0");
  if (!positive(s.path_spacing_m)) return scene_error("path_spacing_m", "must be positive");
  if (s.max_path_points < 0 || s.max_path_points > 256)
    return scene_error("max_path_points", "must be within [0, 256]");
  if (!positive(s.hole_radius_m)) return scene_error("hole_radius_m", "must be positive");
  if (!non_negative(s.bevel_steering_gain) || s.bevel_steering_gain > 1.0)
    return scene_error("bevel_steering_gain", "must be within [0, 1]");
  if (s.gauss_seidel_sweeps < 1 || s.gauss_seidel_sweeps > 1000)
    return scene_error("gauss_seidel_sweeps", "must be within [1, 1000]");
  if (!positive(s.residual_bound_m)) return scene_error("residual_bound_m", "must be positive");
  if (!kernel_isa_available(s.kernel_isa))
    return Error{.message = "this build or CPU has no " + std::string(kernel_isa_name(s.kernel_isa)) + " kernels",
                 .field = "scene.kernel_isa"};
  return Done{};
}

}  // namespace

Result<NeedleTissueModel> make_needle_tissue_model(const NeedleParameters& needle, const NeedleTissueScene& scene,
                                                   std::span<const double> tissue_rest_m) {
  auto needle_model = make_needle_model(needle);
  if (!needle_model.ok()) return needle_model.error();
  if (auto valid = validate_scene(scene); !valid) return valid.error();
  if (tissue_rest_m.size() % 3 != 0)
    return Error{.message = "must hold 3 coordinates per node", .field = "tissue_rest_m"};
  NeedleTissueModel model;
  model.needle = std::move(needle_model).value();
  model.scene = scene;
  model.tissue_rest_m.assign(tissue_rest_m.begin(), tissue_rest_m.end());
  std::size_t box_values = 0;
  for (std::size_t k = 0; k < scene.surfaces.size(); ++k) {
    auto bvh = detail::make_surface_bvh(scene.surfaces[k], tissue_rest_m, "scene.surfaces[" + std::to_string(k) + "]");
    if (!bvh.ok()) return bvh.error();
    bvh.value().box_offset = box_values;
    box_values += 6 * bvh.value().nodes.size();
    model.surface_bvhs.push_back(std::move(bvh).value());
  }
  model.lane_kernels = &detail::needle_lane_kernels(scene.kernel_isa);
  model.compliance_tensor_m_per_n = scene.point_compliance_m_per_n * Eigen::Matrix3d::Identity();
  if (scene.bevel_steering)
    model.bevel_tilt_rad = scene.bevel_steering_gain * (0.5 * std::numbers::pi - needle.bevel_angle_rad);
  return model;
}

Result<NeedleTissueData> make_needle_tissue_data(const NeedleTissueModel& model, const NeedlePose& base) {
  auto needle = make_needle_data(model.needle, base);
  if (!needle.ok()) return needle.error();
  const auto layers = static_cast<std::size_t>(model.layer_count());
  const auto slots = static_cast<std::size_t>(model.slot_count());
  const auto nodes = static_cast<std::size_t>(model.needle.node_count());
  ArenaPlan plan;
  plan.add<LayerState>(layers).add<PathPoint>(static_cast<std::size_t>(model.scene.max_path_points));
  plan.add<ConstraintRow>(slots).add<detail::SweepRow>(slots);
  const bool nodal = model.nodal_compliance();
  const std::size_t points = nodal ? static_cast<std::size_t>(model.max_points()) : 0;
  const auto response_slots = static_cast<std::size_t>(model.response_slots());
  const std::size_t response_values = response_slots * 9 * (model.tissue_rest_m.size() / 3);
  const std::size_t response_work = model.node_response_source != nullptr
                                        ? 2 * static_cast<std::size_t>(model.node_response_source->free_dof_count())
                                        : 0;
  plan.add<std::int32_t>(slots + 1);
  plan.add<std::int32_t>(points).add<std::int32_t>(points).add<std::int32_t>(points);
  plan.add<std::int32_t>(response_slots).add<std::int64_t>(response_slots);
  // W: rows of m values padded to whole lanes of the kernels (the last lower-triangle row
  // may run past its last padded row up to the lanes' multiple). Low rank: 3 freedoms per
  // free needle node and per constraint point's tissue node, and slots for rows, padded alike.
  const auto lanes = [](std::size_t count) {
    return (count + detail::kCombinedLanes - 1) / detail::kCombinedLanes * detail::kCombinedLanes;
  };
  const std::size_t padded_slots = lanes(slots), compliance = slots * padded_slots + detail::kCombinedLanes;
  const std::size_t needle_freedoms = nodal ? lanes(3 * static_cast<std::size_t>(model.needle.element_count)) : 0;
  const std::size_t tissue_freedoms = lanes(3 * points), freedoms = needle_freedoms + tissue_freedoms;
  const std::size_t entries = nodal ? detail::kMaxCombinedTerms * slots : 0;
  plan.add<std::int32_t>(entries).add<std::int32_t>(entries);
  // The buffers of doubles, each starting on a whole lanes' width for the kernels' loads.
  for (std::size_t count : {model.surface_box_values(), slots, slots, compliance, slots, slots, 6 * nodes,
                            tissue_freedoms * tissue_freedoms, entries, freedoms * padded_slots,
                            freedoms * padded_slots, response_values, response_work})
    plan.add<double>(count, detail::kLaneBytes);
  NeedleTissueData data(Arena("needle_tissue_data", plan.bytes()), std::move(needle).value());
  auto layer_states = data.arena.allocate<LayerState>("layers", layers);
  auto path = data.arena.allocate<PathPoint>("path points", static_cast<std::size_t>(model.scene.max_path_points));
  auto rows = data.arena.allocate<ConstraintRow>("constraint rows", slots);
  auto sweep_rows = data.arena.allocate<detail::SweepRow>("sweep rows", slots);
  if (!layer_states.ok()) return layer_states.error();
  if (!path.ok()) return path.error();
  if (!rows.ok()) return rows.error();
  if (!sweep_rows.ok()) return sweep_rows.error();
  data.sweep_rows = sweep_rows.value();
  data.layers = layer_states.value();
  data.path = path.value();
  data.rows = rows.value();
  struct Buffer {
    std::span<double>* span;
    std::size_t count;
    const char* what;
  };
  const Buffer buffers[] = {{&data.surface_boxes, model.surface_box_values(), "surface boxes"},
                            {&data.slot_forces, slots, "slot forces"},
                            {&data.applied_forces, slots, "applied forces"},
                            {&data.compliance, compliance, "compliance"},
                            {&data.row_forces, slots, "row forces"},
                            {&data.row_gaps, slots, "row gaps"},
                            {&data.nodal_forces, 6 * nodes, "nodal forces"},
                            {&data.low_rank.tissue_compliance, tissue_freedoms * tissue_freedoms, "tissue compliance"},
                            {&data.low_rank.coefficients, entries, "compliance coefficients"},
                            {&data.low_rank.row_fields, freedoms * padded_slots, "row fields"},
                            {&data.low_rank.fields, freedoms * padded_slots, "fields"},
                            {&data.responses_m_per_n, response_values, "full-order responses"},
                            {&data.response_work, response_work, "full-order response work"}};
  for (const Buffer& b : buffers) {
    auto carved = data.arena.allocate<double>(b.what, b.count, detail::kLaneBytes);
    if (!carved.ok()) return carved.error();
    *b.span = carved.value();
  }
  auto first_rows = data.arena.allocate<std::int32_t>("point first rows", slots + 1);
  if (!first_rows.ok()) return first_rows.error();
  data.point_first_row = first_rows.value();
  auto distinct = data.arena.allocate<std::int32_t>("distinct tissue nodes", points);
  auto index = data.arena.allocate<std::int32_t>("point tissue indices", points);
  auto response_slot = data.arena.allocate<std::int32_t>("distinct response slots", points);
  auto response_nodes = data.arena.allocate<std::int32_t>("response nodes", response_slots);
  auto response_used = data.arena.allocate<std::int64_t>("response uses", response_slots);
  if (!distinct.ok()) return distinct.error();
  if (!index.ok()) return index.error();
  if (!response_slot.ok()) return response_slot.error();
  if (!response_nodes.ok()) return response_nodes.error();
  if (!response_used.ok()) return response_used.error();
  data.distinct_tissue_nodes = distinct.value();
  data.point_tissue_index = index.value();
  data.distinct_response_slot = response_slot.value();
  data.response_nodes = response_nodes.value();
  data.response_used = response_used.value();
  std::fill(data.response_nodes.begin(), data.response_nodes.end(), -1);
  std::fill(data.response_used.begin(), data.response_used.end(), -1);
  auto local_sources = data.arena.allocate<std::int32_t>("compliance local sources", entries);
  auto sources = data.arena.allocate<std::int32_t>("compliance sources", entries);
  if (!local_sources.ok()) return local_sources.error();
  if (!sources.ok()) return sources.error();
  data.low_rank.local_sources = local_sources.value();
  data.low_rank.sources = sources.value();
  for (std::size_t l = 0; l < layers; ++l) {
    const Point3& p = model.scene.layers[l].surface_point_m;
    if (model.scene.layers[l].surface < 0)
      data.layers[l].surface = tissue_point_at(model, Eigen::Vector3d(p[0], p[1], p[2]), {});
  }
  refresh_surfaces(model, data, {});
  return data;
}

void refresh_surfaces(const NeedleTissueModel& model, NeedleTissueData& data,
                      std::span<const double> displacements_m) noexcept {
  for (const detail::SurfaceBvh& bvh : model.surface_bvhs)
    detail::refit_surface_bvh(bvh, data.surface_boxes.subspan(bvh.box_offset, 6 * bvh.nodes.size()),
                              model.tissue_rest_m, displacements_m);
}

}  // namespace nav
