// Init time of the operating loop: checks the options against the reduced model and the
// filter, derives the look-ahead, couples the needle to the liver, and builds the data.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "nav/loop/operating_loop.hpp"

namespace nav {
namespace {

Error option_error(const char* field, const std::string& message) {
  return Error{message, "", 0, std::string("operating_loop.") + field};
}

}  // namespace

OperatingLoopData::OperatingLoopData(ReducedData reduced_data, ReducedData lookahead_data, ReducedKalmanData filter_data,
                                     PoseTrack needle_track, PoseTrack probe_track, BreathingPredictor breathing_predictor,
                                     std::size_t pending_capacity)
    : reduced(std::move(reduced_data)),
      lookahead(std::move(lookahead_data)),
      filter(std::move(filter_data)),
      needle(std::move(needle_track)),
      probe(std::move(probe_track)),
      breathing(std::move(breathing_predictor)),
      pending(pending_capacity) {}

Result<OperatingLoopModel> make_operating_loop_model(ReducedModel reduced, ReducedKalmanModel filter,
                                                     const OperatingLoopOptions& options) {
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
  if (filter.point_count < 1) return option_error("filter", "observes no point (point 0 is the tumour)");
  if (filter.r != reduced.basis_size()) return option_error("filter", "belongs to a reduced model of another size");
  if (reduced.basis_size() > kLoopMaxBasisSize)
    return option_error("reduced", "has " + std::to_string(reduced.basis_size()) + " coordinates; a loop carries at most " +
                                       std::to_string(kLoopMaxBasisSize));
  const double tissue_period_s = static_cast<double>(options.tissue_every_ticks) * static_cast<double>(options.tick_period_ns) * 1e-9;
  const double step_s = reduced.options().step_s;
  if (std::abs(step_s - tissue_period_s) > 1e-9 * tissue_period_s)
    return option_error("tissue_every_ticks", "tissue_every_ticks * tick_period_ns is " + std::to_string(tissue_period_s) +
                                                  " s but the reduced model steps " + std::to_string(step_s) + " s");
  OperatingLoopModel model;
  model.lookahead_steps = std::max(1, static_cast<int>(std::ceil(static_cast<double>(options.display_latency_ns) * 1e-9 / step_s - 1e-9)));
  model.lookahead_decay = std::pow(filter.decay, model.lookahead_steps);
  if (!(options.breathing.axis.norm() > 0.0)) return option_error("breathing.axis", "must not be zero");
  model.breathing_axis = options.breathing.axis.normalized();
  model.reduced = std::move(reduced);
  model.filter = std::move(filter);
  model.options = options;
  return model;
}

Result<OperatingLoopModel> make_operating_loop_model(ReducedModel reduced, ReducedKalmanModel filter, const OperatingLoopOptions& options,
                                                     const OperatingLoopNeedleOptions& needle, const TetMesh& mesh) {
  auto built = make_operating_loop_model(std::move(reduced), std::move(filter), options);
  if (!built.ok()) return built.error();
  OperatingLoopModel model = std::move(built).value();
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
                                                               " nodes; a loop carries at most " + std::to_string(kLoopMaxNeedleNodes));
  const RigidPose& base = needle.base_in_marker;
  if (!base.position_m.allFinite() || std::abs(base.rotation.norm() - 1.0) > 1e-9)
    return option_error("needle.base_in_marker", "must be a finite position and a unit quaternion");
  auto holder = std::make_shared<OperatingLoopNeedleModel>(model.reduced, base, p.length_m);
  auto coupled = make_coupled_needle_model(p, needle.scene, holder->tissue, mesh, needle.max_point_forces, options.tissue_every_ticks);
  if (!coupled.ok()) {  // its field is put under operating_loop.needle
    Error error = coupled.error();
    error.field = "operating_loop.needle." + error.field;
    return error;
  }
  holder->coupled = std::move(coupled).value();
  model.needle = std::move(holder);
  return model;
}

Result<OperatingLoopData> make_operating_loop_data(const OperatingLoopModel& model) {
  auto reduced = make_reduced_data(model.reduced);
  if (!reduced.ok()) return reduced.error();
  auto lookahead = make_reduced_data(model.reduced);
  if (!lookahead.ok()) return lookahead.error();
  auto filter = make_reduced_kalman_data(model.filter);
  if (!filter.ok()) return filter.error();
  auto needle = PoseTrack::create(model.options.needle);
  if (!needle.ok()) return needle.error();
  auto probe = PoseTrack::create(model.options.probe);
  if (!probe.ok()) return probe.error();
  auto breathing = BreathingPredictor::create(model.options.breathing);
  if (!breathing.ok()) return breathing.error();
  OperatingLoopData data(std::move(reduced).value(), std::move(lookahead).value(), std::move(filter).value(),
                         std::move(needle).value(), std::move(probe).value(), std::move(breathing).value(),
                         model.options.max_pending_observations);
  if (model.needle) {  // idle at its holder's pose in the marker frame until the needle is seen
    data.needle_base = model.needle->base_in_marker;
    auto coupled = make_coupled_needle_data(model.needle->coupled, to_needle_pose(data.needle_base));
    if (!coupled.ok()) return coupled.error();
    data.needle_model.emplace(std::move(coupled).value());
  }
  return data;
}

}  // namespace nav
