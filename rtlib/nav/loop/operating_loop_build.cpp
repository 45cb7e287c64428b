// Init time of the operating loop: checks the options against the liver's rungs and their
// filters, derives the look-ahead and the maps between rungs, couples the needle to every
// rung, and builds the data.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "nav/loop/operating_loop.hpp"
#include "nav/needle/missing_node_compliance.hpp"
#include "nav/reduced/reduced_tables.hpp"

namespace nav {
namespace {

Error option_error(const std::string& field, const std::string& message) {
  return Error{.message = message, .field = "operating_loop." + field};
}

/// A liver rung as given, and the names its errors use.
struct RungInput {
  ReducedModel reduced;
  ReducedKalmanModel filter;
  std::string reduced_field, filter_field;
};

Status check_options(const OperatingLoopOptions& options) {
  if (options.tick_period_ns <= 0) return option_error("tick_period_ns", "must be positive");
  if (options.tissue_every_ticks < 1) return option_error("tissue_every_ticks", "must be at least 1");
  if (options.display_latency_ns < 0) return option_error("display_latency_ns", "must not be negative");
  if (!options.needle_tip_in_marker_m.allFinite()) return option_error("needle_tip_in_marker_m", "must be finite");
  if (!options.diaphragm_per_marker.allFinite()) return option_error("diaphragm_per_marker", "must be finite");
  if (!std::isfinite(options.respiratory_reference_m)) return option_error("respiratory_reference_m", "must be finite");
  const RigidPose& registration = options.model_from_tracker;
  if (!registration.position_m.allFinite() || std::abs(registration.rotation.norm() - 1.0) > 1e-9)
    return option_error("model_from_tracker", "must be a finite position and a unit quaternion");
  if (options.max_pending_observations < 1) return option_error("max_pending_observations", "must be at least 1");
  if (options.ultrasound_max_age_ns <= 0) return option_error("ultrasound_max_age_ns", "must be positive");
  if (!(options.breathing.axis.norm() > 0.0)) return option_error("breathing.axis", "must not be zero");
  return Done{};
}

Status check_rung(const RungInput& rung, const OperatingLoopOptions& options) {
  const ReducedKalmanModel& filter = rung.filter;
  if (filter.point_count < 1) return option_error(rung.filter_field, "observes no point (point 0 is the tumour)");
  if (filter.r != rung.reduced.basis_size())
    return option_error(rung.filter_field, "belongs to a reduced model of another size");
  if (rung.reduced.basis_size() > kLoopMaxBasisSize)
    return option_error(rung.reduced_field, "has " + std::to_string(rung.reduced.basis_size()) +
                                                " coordinates; a loop carries at most " +
                                                std::to_string(kLoopMaxBasisSize));
  const double tissue_period_s =
      static_cast<double>(options.tissue_every_ticks) * static_cast<double>(options.tick_period_ns) * 1e-9;
  const double step_s = rung.reduced.options().step_s;
  if (std::abs(step_s - tissue_period_s) > 1e-9 * tissue_period_s)
    return option_error("tissue_every_ticks", "tissue_every_ticks * tick_period_ns is " +
                                                  std::to_string(tissue_period_s) + " s but the reduced model steps " +
                                                  std::to_string(step_s) + " s");
  return Done{};
}

/// The needle coupled to one rung's liver; errors put under operating_loop.needle.
Result<std::shared_ptr<const OperatingLoopNeedleModel>> couple_needle(const ReducedModel& liver,
                                                                      const OperatingLoopNeedleOptions& needle,
                                                                      const OperatingLoopOptions& options,
                                                                      const TetMesh& mesh,
                                                                      std::size_t other_point_forces) {
  auto holder = std::make_shared<OperatingLoopNeedleModel>(liver, needle.marker_from_base, needle.parameters.length_m);
  auto coupled = make_coupled_needle_model(needle.parameters, needle.scene, holder->tissue, mesh,
                                           needle.max_point_forces, options.tissue_every_ticks);
  if (!coupled.ok()) {
    Error error = coupled.error();
    error.field = "operating_loop.needle." + error.field;
    return error;
  }
  if (needle.missing_compliance_source != nullptr) {
    auto missing =
        static_missing_node_compliance(liver, *needle.missing_compliance_source, needle.missing_compliance_radius_m);
    if (!missing.ok()) {
      Error error = missing.error();
      error.field = "operating_loop.needle.missing_compliance_source (" + error.field + ")";
      return error;
    }
    coupled.value().interaction.missing_compliance = std::move(missing).value();
  }
  holder->coupled = std::move(coupled).value();
  holder->coupled.other_point_forces = other_point_forces;
  return std::shared_ptr<const OperatingLoopNeedleModel>(std::move(holder));
}

/// The needle's own checks against the loop's rates and output sizes.
Status check_needle(const OperatingLoopNeedleOptions& needle, const OperatingLoopOptions& options) {
  const NeedleParameters& p = needle.parameters;
  if (auto valid = validate_needle_parameters(p); !valid) {  // its field is needle.<parameter>
    Error error = valid.error();
    error.field = "operating_loop.needle.parameters." + error.field.substr(error.field.rfind('.') + 1);
    return error;
  }
  const double tick_s = static_cast<double>(options.tick_period_ns) * 1e-9;
  if (std::abs(p.step_s - tick_s) > 1e-9 * tick_s)
    return option_error("needle.parameters.step_s", "is " + std::to_string(p.step_s) + " s but the loop ticks every " +
                                                        std::to_string(tick_s) + " s");
  if (p.element_count + 1 > kLoopMaxNeedleNodes)
    return option_error("needle.parameters.element_count", "gives " + std::to_string(p.element_count + 1) +
                                                               " nodes; a loop carries at most " +
                                                               std::to_string(kLoopMaxNeedleNodes));
  const RigidPose& base = needle.marker_from_base;
  if (!base.position_m.allFinite() || std::abs(base.rotation.norm() - 1.0) > 1e-9)
    return option_error("needle.marker_from_base", "must be a finite position and a unit quaternion");
  return Done{};
}

/// The ligaments against one rung's liver: their attachment nodes in its mesh, its scene's
/// stabilising springs and room for their point forces beside the needle's.
Status check_ligaments(const OrganLigaments& ligaments, const RungInput& rung,
                       const OperatingLoopNeedleOptions* needle) {
  const OrganAttachment& a = ligaments.attachment;
  const detail::ReducedTables& t = rung.reduced.tables();
  for (const std::int32_t node : a.nodes)
    if (node < 0 || node >= t.node_count)
      return option_error("ligaments", "are attached to node " + std::to_string(node) + ", which " +
                                           rung.reduced_field + "'s liver does not have");
  if (t.spring_stiffness_n_m != a.spring_stiffness_n_m)
    return option_error("ligaments",
                        rung.reduced_field + "'s scene does not carry their stabilising springs (declare_attachment)");
  const std::size_t needed = a.nodes.size() + (needle ? needle->max_point_forces : 0);
  if (needed > t.max_point_forces)
    return option_error("ligaments", "need " + std::to_string(needed) + " point forces (" +
                                         std::to_string(a.nodes.size()) + " attachment nodes" +
                                         (needle ? " and the needle's max_point_forces" : "") + ") but " +
                                         rung.reduced_field + "'s scene takes " + std::to_string(t.max_point_forces));
  return Done{};
}

/// The maps of rung `i` from rung i - 1 of `ladder`.
void add_maps_from_below(const ReducedLadderModel& ladder, int i, OperatingLoopRung& rung) {
  const std::span<const double> up = ladder.transfer(i - 1);
  const int rows = rung.reduced.basis_size(), cols = ladder.reduced_rung(i - 1).basis_size();
  rung.up_from_below.assign(up.begin(), up.end());
  rung.down_to_below.resize(up.size());
  for (int a = 0; a < rows; ++a)
    for (int b = 0; b < cols; ++b)
      rung.down_to_below[static_cast<std::size_t>(b * rows + a)] = up[static_cast<std::size_t>(a * cols + b)];
  rung.unseen_prior = unseen_directions_prior(rung.filter, up, cols);
}

Result<OperatingLoopModel> make_model(std::vector<RungInput> rungs, std::optional<ReducedLadderModel> ladder,
                                      const OperatingLoopOptions& options, const OperatingLoopNeedleOptions* needle,
                                      const TetMesh* mesh, std::shared_ptr<const OrganLigaments> ligaments) {
  if (Status valid = check_options(options); !valid.ok()) return valid.error();
  for (const RungInput& rung : rungs) {
    if (Status valid = check_rung(rung, options); !valid.ok()) return valid.error();
    if (ligaments)
      if (Status valid = check_ligaments(*ligaments, rung, needle); !valid.ok()) return valid.error();
  }
  const std::size_t ligament_forces = ligaments ? ligaments->attachment.nodes.size() : 0;
  if (needle)
    if (Status valid = check_needle(*needle, options); !valid.ok()) return valid.error();
  OperatingLoopModel model;
  const double step_s = rungs.front().reduced.options().step_s;
  model.lookahead_steps =
      std::max(1, static_cast<int>(std::ceil(static_cast<double>(options.display_latency_ns) * 1e-9 / step_s - 1e-9)));
  model.breathing_axis = options.breathing.axis.normalized();
  model.options = options;
  for (std::size_t i = 0; i < rungs.size(); ++i) {
    OperatingLoopRung rung;
    rung.reduced = std::move(rungs[i].reduced);
    rung.filter = std::move(rungs[i].filter);
    rung.lookahead_decay = std::pow(rung.filter.decay, model.lookahead_steps);
    if (i > 0) add_maps_from_below(*ladder, static_cast<int>(i), rung);
    if (needle) {
      auto coupled = couple_needle(rung.reduced, *needle, options, *mesh, ligament_forces);
      if (!coupled.ok()) return coupled.error();
      rung.needle = std::move(coupled).value();
    }
    model.rungs.push_back(std::move(rung));
  }
  model.ladder = std::move(ladder);
  model.ligaments = std::move(ligaments);
  return model;
}

/// The ligaments at rest, their liver's attachment nodes at their rest positions.
Result<OperatingLoopLigamentsData> make_ligaments_data(const OrganLigaments& ligaments, std::int64_t liver_nodes) {
  auto tissue = make_frame_tissue_data(ligaments.model);
  if (!tissue.ok()) return tissue.error();
  const OrganAttachment& a = ligaments.attachment;
  OperatingLoopLigamentsData data{std::move(tissue).value(), make_attachment_buffers(a),
                                  std::vector<double>(3 * a.nodes.size()),
                                  std::vector<double>(3 * static_cast<std::size_t>(liver_nodes))};
  for (std::size_t k = 0; k < a.nodes.size(); ++k)
    std::copy_n(a.node_rest_positions_m.begin() + static_cast<std::ptrdiff_t>(3 * k), 3,
                data.organ_positions_m.begin() + 3 * static_cast<std::ptrdiff_t>(a.nodes[k]));
  return data;
}

}  // namespace

OperatingLoopData::OperatingLoopData(std::vector<OperatingLoopRungData> rung_data, std::size_t workspace_values,
                                     PoseTrack needle_track, PoseTrack probe_track,
                                     BreathingPredictor breathing_predictor, std::size_t pending_capacity)
    : rungs(std::move(rung_data)),
      transfer_workspace(workspace_values),
      needle(std::move(needle_track)),
      probe(std::move(probe_track)),
      breathing(std::move(breathing_predictor)),
      pending(pending_capacity) {}

Result<OperatingLoopModel> make_operating_loop_model(ReducedModel reduced, ReducedKalmanModel filter,
                                                     const OperatingLoopOptions& options,
                                                     std::shared_ptr<const OrganLigaments> ligaments) {
  std::vector<RungInput> rungs;
  rungs.push_back({std::move(reduced), std::move(filter), "reduced", "filter"});
  return make_model(std::move(rungs), std::nullopt, options, nullptr, nullptr, std::move(ligaments));
}

Result<OperatingLoopModel> make_operating_loop_model(ReducedModel reduced, ReducedKalmanModel filter,
                                                     const OperatingLoopOptions& options,
                                                     const OperatingLoopNeedleOptions& needle, const TetMesh& mesh,
                                                     std::shared_ptr<const OrganLigaments> ligaments) {
  std::vector<RungInput> rungs;
  rungs.push_back({std::move(reduced), std::move(filter), "reduced", "filter"});
  return make_model(std::move(rungs), std::nullopt, options, &needle, &mesh, std::move(ligaments));
}

Result<OperatingLoopModel> make_operating_loop_model(const ReducedLadderModel& ladder,
                                                     std::vector<ReducedKalmanModel> filters,
                                                     const OperatingLoopOptions& options,
                                                     const OperatingLoopNeedleOptions* needle, const TetMesh* mesh,
                                                     std::shared_ptr<const OrganLigaments> ligaments) {
  if (ladder.has_full_order())
    return option_error(
        "ladder",
        "has a full-order rung; a loop's ladder has reduced rungs only (its filter needs reduced coordinates)");
  if (filters.size() != static_cast<std::size_t>(ladder.reduced_rung_count()))
    return option_error("filters", "has " + std::to_string(filters.size()) + " filters for " +
                                       std::to_string(ladder.reduced_rung_count()) + " rungs (one per rung)");
  if (needle && !mesh) return option_error("needle", "needs the liver's mesh");
  std::vector<RungInput> rungs;
  for (std::size_t i = 0; i < filters.size(); ++i) {
    const std::string index = "[" + std::to_string(i) + "]";
    rungs.push_back(
        {ladder.reduced_rung(static_cast<int>(i)), std::move(filters[i]), "ladder.rungs" + index, "filters" + index});
  }
  return make_model(std::move(rungs), ladder, options, needle, mesh, std::move(ligaments));
}

Result<OperatingLoopData> make_operating_loop_data(const OperatingLoopModel& model) {
  std::vector<OperatingLoopRungData> rungs;
  int max_r = 0;
  for (const OperatingLoopRung& rung : model.rungs) {
    auto reduced = make_reduced_data(rung.reduced);
    if (!reduced.ok()) return reduced.error();
    auto lookahead = make_reduced_data(rung.reduced);
    if (!lookahead.ok()) return lookahead.error();
    auto filter = make_reduced_kalman_data(rung.filter);
    if (!filter.ok()) return filter.error();
    OperatingLoopRungData data{std::move(reduced).value(), std::move(lookahead).value(), std::move(filter).value(),
                               std::nullopt};
    if (rung.needle) {  // idle at its holder's pose in the marker frame until the needle is seen
      auto coupled = make_coupled_needle_data(rung.needle->coupled, to_needle_pose(rung.needle->marker_from_base));
      if (!coupled.ok()) return coupled.error();
      data.needle_model.emplace(std::move(coupled).value());
    }
    rungs.push_back(std::move(data));
    max_r = std::max(max_r, rung.reduced.basis_size());
  }
  auto needle = PoseTrack::create(model.options.needle);
  if (!needle.ok()) return needle.error();
  auto probe = PoseTrack::create(model.options.probe);
  if (!probe.ok()) return probe.error();
  auto breathing = BreathingPredictor::create(model.options.breathing);
  if (!breathing.ok()) return breathing.error();
  OperatingLoopData data(std::move(rungs), static_cast<std::size_t>(max_r) * static_cast<std::size_t>(max_r),
                         std::move(needle).value(), std::move(probe).value(), std::move(breathing).value(),
                         model.options.max_pending_observations);
  if (model.has_needle()) data.needle_base = model.rungs.front().needle->marker_from_base;
  if (model.ligaments) {
    auto ligaments = make_ligaments_data(*model.ligaments, model.rungs.front().reduced.node_count());
    if (!ligaments.ok()) return ligaments.error();
    data.ligaments.emplace(std::move(ligaments).value());
  }
  return data;
}

Result<LiverDisplayScratch> make_liver_display_scratch(const OperatingLoopModel& model) {
  LiverDisplayScratch scratch;
  for (const OperatingLoopRung& rung : model.rungs) {
    auto data = make_reduced_data(rung.reduced);
    if (!data.ok()) return data.error();
    scratch.rungs.push_back(std::move(data).value());
  }
  return scratch;
}

}  // namespace nav
