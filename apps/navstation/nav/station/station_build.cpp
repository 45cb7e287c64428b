#include "nav/station/station_build.hpp"

#include <algorithm>
#include <charconv>
#include <stdexcept>

#include "nav/connective/organ_attachment.hpp"
#include "nav/reduced/reduced_artifact.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/station/security_roles.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/station_liver.hpp"
#include "nav/station/station_needle_surfaces.hpp"

namespace nav::station {

namespace {

/// An Error of a builder, placed at `section`'s line of the scene file.
Error at_section(const Error& inner, const Scene& scene, int line, const std::string& section) {
  Error error{inner.file.empty() ? inner.message : inner.describe(), scene.source_path, line, section};
  if (inner.file.empty() && !inner.field.empty()) error.field += " (" + inner.field + ")";
  return error;
}

/// The frames the scene's models are placed by.
Status check_frames(const calibration::FrameTree& tree, const Scene& scene) {
  std::vector<std::string> needed{"tracker", "liver_model", "probe_marker", "image_plane"};
  if (scene.needle) needed.insert(needed.end(), {"needle_base", "needle_tip"});
  const std::vector<std::string> frames = tree.frames();
  for (const std::string& name : needed)
    if (std::find(frames.begin(), frames.end(), name) == frames.end())
      return Error{.message = "the URDF " + scene.frames.urdf_path + " has no frame '" + name + "'",
                   .file = scene.source_path,
                   .line = scene.frames.line,
                   .field = "frames.urdf"};
  return Done{};
}

/// An Error of the ladder's builder placed at its scene key: its rungs[0] is liver.model's
/// artifact, rungs[i] the escalation's rungs[i - 1], step_s and integrator those of the full
/// order on top, any other field the escalation key of that name.
Error ladder_error(const Error& inner, const Scene& scene) {
  const EscalationSettings& e = *scene.liver.escalation;
  std::string field = inner.field;
  std::string key = "liver.model.escalation." + field;
  int line = e.line;
  if (field.rfind("rungs[", 0) == 0) {
    const std::size_t close = field.find(']');
    std::size_t rung = 0;
    std::from_chars(field.data() + 6, field.data() + close, rung);
    field = close + 2 <= field.size() ? field.substr(close + 2) : std::string();
    key = rung == 0 ? "liver.model.artifact" : "liver.model.escalation.rungs[" + std::to_string(rung - 1) + "]";
    line = rung == 0 ? scene.liver.line : rung <= e.rungs.size() ? e.rungs[rung - 1].line : e.line;
  } else if (field == "step_s" || field == "integrator") {
    key = "liver.model.escalation.full_order_on_top";
  } else {
    field.clear();
  }
  return at_section(Error{.message = inner.message, .file = inner.file, .line = inner.line, .field = field}, scene,
                    line, key);
}

/// The full-order law of the reduced rungs' force kind, with their step, integrator and damping
/// (what the full order on top of a ladder must share with them).
TissueSolverOptions ladder_solver(ReducedForceKind kind, const ReducedSolverOptions& reduced) {
  TissueSolverOptions solver = reduction_solver_options(kind);
  solver.step_s = reduced.step_s;
  solver.integrator =
      reduced.integrator == ReducedIntegrator::quasi_static ? Integrator::quasi_static : Integrator::implicit_euler;
  solver.rayleigh_mass_per_s = reduced.rayleigh_mass_per_s;
  solver.rayleigh_stiffness_s = reduced.rayleigh_stiffness_s;
  return solver;
}

Status build_ligaments(const Scene& scene, StationModels& models) {
  auto ligaments = make_scene_ligaments(scene, models.liver.mesh, models.liver.scene);
  if (!ligaments.ok()) return ligaments.error();
  auto data = make_frame_tissue_data(ligaments.value().model);
  if (!data.ok()) return at_section(data.error(), scene, scene.ligaments->line, "ligaments");
  models.ligaments = std::move(ligaments).value();
  models.ligament_data = std::move(data).value();
  return Done{};
}

Status build_needle(const Scene& scene, StationModels& models) {
  auto interaction = station_needle_interaction(scene, models.liver.mesh, models.liver.tumour_m);
  if (!interaction.ok()) return interaction.error();  // it names its layer's line
  std::vector<double> rest_m;
  rest_m.reserve(3 * models.liver.mesh.nodes_m.size());
  for (const Point3& node : models.liver.mesh.nodes_m) rest_m.insert(rest_m.end(), node.begin(), node.end());
  auto model = make_needle_tissue_model(scene.needle->parameters, interaction.value(), rest_m);
  if (!model.ok()) return model.error();
  auto data = make_needle_tissue_data(model.value(), NeedlePose{});
  if (!data.ok()) return data.error();
  models.needle = std::move(model).value();
  models.needle_data = std::move(data).value();
  return Done{};
}

}  // namespace

Result<OrganLigaments> make_scene_ligaments(const Scene& scene, const TetMesh& mesh, TissueScene& liver_scene) {
  const LigamentSettings& settings = *scene.ligaments;
  FrameTissueOptions options;
  options.step_s = 1.0 / scene.station.tissue_rate_hz;
  options.rayleigh_mass_per_s = settings.rayleigh_mass_per_s;
  options.solver = settings.solver;
  auto ligaments = make_organ_ligaments(mesh, settings.blocks, settings.material, options, liver_scene.gravity_m_s2);
  if (!ligaments.ok()) return at_section(ligaments.error(), scene, settings.line, "ligaments");
  declare_attachment(ligaments.value().attachment, liver_scene);
  return ligaments;
}

Result<std::vector<ReducedRungSpec>> load_reduced_rungs(const Scene& scene, const TetMesh& mesh) {
  const LiverSettings& settings = scene.liver;
  std::vector<ReducedRungSpec> rungs;
  auto base = load_reduced_basis(settings.reduced_artifact_path, &mesh);
  if (!base.ok()) return at_section(base.error(), scene, settings.line, "liver.model.artifact");
  rungs.push_back({std::move(base).value(), settings.reduced});
  if (!settings.escalation) return rungs;
  const EscalationSettings& e = *settings.escalation;
  for (std::size_t i = 0; i < e.rungs.size(); ++i) {
    const std::string key = "liver.model.escalation.rungs[" + std::to_string(i) + "]";
    auto basis = load_reduced_basis(e.rungs[i].artifact_path, &mesh);
    if (!basis.ok()) return at_section(basis.error(), scene, e.rungs[i].line, key);
    if (basis.value().force_kind != rungs[0].basis.force_kind)
      return Error{.message = e.rungs[i].artifact_path +
                              ": its force kind differs from liver.model.artifact's (the rungs share one element law)",
                   .file = scene.source_path,
                   .line = e.rungs[i].line,
                   .field = key};
    rungs.push_back({std::move(basis).value(), settings.reduced});
  }
  return rungs;
}

Result<ReducedModel> make_scene_reduced_model(const Scene& scene, const TetMesh& mesh, const TissueScene& tissue,
                                              const ReducedRungSpec& rung) {
  auto model =
      make_reduced_model(mesh, tissue, reduction_solver_options(rung.basis.force_kind), rung.basis, rung.options);
  if (!model.ok()) return at_section(model.error(), scene, scene.liver.line, "liver.model");
  return model;
}

Result<ReducedLadderModel> make_scene_ladder(const Scene& scene, const TetMesh& mesh, const TissueScene& tissue,
                                             std::span<const ReducedRungSpec> rungs) {
  const EscalationSettings& e = *scene.liver.escalation;
  const TissueSolverOptions solver = ladder_solver(rungs[0].basis.force_kind, scene.liver.reduced);
  auto model = make_reduced_ladder_model(mesh, tissue, solver, rungs, e.full_order_on_top, e.options);
  if (!model.ok()) return ladder_error(model.error(), scene);
  return model;
}

namespace {

Status build_liver_model(const Scene& scene, LiverModels& liver) {
  const LiverSettings& settings = scene.liver;
  if (settings.rung == LiverRung::full) {
    auto model = make_tet_fem_model(liver.mesh, liver.scene, settings.full);
    if (!model.ok()) return at_section(model.error(), scene, settings.line, "liver.model");
    auto data = make_tet_fem_data(model.value());
    if (!data.ok()) return at_section(data.error(), scene, settings.line, "liver.model");
    liver.full = std::move(model).value();
    liver.full_data = std::move(data).value();
    return Done{};
  }
  auto rungs = load_reduced_rungs(scene, liver.mesh);
  if (!rungs.ok()) return rungs.error();
  if (settings.escalation) {
    auto ladder = make_scene_ladder(scene, liver.mesh, liver.scene, rungs.value());
    if (!ladder.ok()) return ladder.error();
    auto data = make_reduced_ladder_data(ladder.value());
    if (!data.ok()) return at_section(data.error(), scene, settings.escalation->line, "liver.model.escalation");
    liver.ladder = std::move(ladder).value();
    liver.ladder_data.emplace(std::move(data).value());
    return Done{};
  }
  auto model = make_scene_reduced_model(scene, liver.mesh, liver.scene, rungs.value().front());
  if (!model.ok()) return model.error();
  auto data = make_reduced_data(model.value());
  if (!data.ok()) return at_section(data.error(), scene, settings.line, "liver.model");
  liver.reduced = std::move(model).value();
  liver.reduced_data = std::move(data).value();
  return Done{};
}

}  // namespace

Result<BuiltStation> build_station(Scene scene) {
  auto frames = calibration::FrameTree::load(scene.frames.urdf_path);
  if (!frames.ok()) return at_section(frames.error(), scene, scene.frames.line, "frames.urdf");
  const Status frames_complete = check_frames(frames.value(), scene);
  if (!frames_complete.ok()) return frames_complete.error();
  const Status network = dds::check_network(station_network(scene.topics.domain_id, "nav_station", scene.network));
  if (!network.ok()) {
    const std::string& field = network.error().field;
    return Error{.message = network.error().message,
                 .file = scene.source_path,
                 .line = scene.network.line,
                 .field = field == "local_address" ? "network.local_address" : "network.peers"};
  }
  // The station's own identity only: each host holds the keys of the roles it runs.
  const Status secured = dds::check_security(security_files(scene.network.security, Role::station));
  if (!secured.ok()) {
    const Error& e = secured.error();
    return Error{.message = e.message + (e.file.empty() ? "" : ": " + e.file) + " (the station's files)",
                 .file = scene.source_path,
                 .line = scene.network.security.line,
                 .field = e.field};
  }
  BuiltStation built{StationModels{std::move(scene), std::move(frames).value(), {}, {}, {}, {}, {}}, {}};
  StationModels& models = built.models;
  const Scene& s = models.scene;

  auto liver = make_station_liver(s);
  if (!liver.ok()) return liver.error();
  models.liver.mesh = std::move(liver.value().mesh);
  models.liver.scene = std::move(liver.value().scene);
  models.liver.tumour_m = liver.value().tumour_m;
  Status step = Done{};
  if (s.ligaments) {
    step = build_ligaments(s, models);
    if (!step.ok()) return step.error();
  }
  step = build_liver_model(s, models.liver);
  if (!step.ok()) return step.error();
  if (s.needle) {
    step = build_needle(s, models);
    if (!step.ok())
      return step.error().file.empty() ? at_section(step.error(), s, s.needle->line, "needle") : step.error();
  }
  built.footprint = measure_footprint(models);
  return built;
}

}  // namespace nav::station
