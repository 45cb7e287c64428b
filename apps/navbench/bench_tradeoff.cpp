// navbench tradeoff. Per mesh level: the reduction scene (liver_reduction_scene; for the
// generated liver, its attachments held, gravity along -z, a stiffer tumour and a diaphragm
// patch), the seeded training loads solved with the full-order corotational model, and the
// held-out loads solved with the full-order corotational model and, for the first held-out
// load of each kind, with the neo-Hookean reference. Each rung is then measured twice:
//  - error: its static equilibrium against the neo-Hookean reference (error_rms_m: RMS over
//    those loads of the nodal RMS; error_max_m, target_error_m: largest over them;
//    error_rms_pct: the worst load's RMS in % of its largest displacement) and, on every
//    held-out load, against the full-order corotational model (*_vs_corotational);
//  - speed: the median and 99th percentile of its real-time step (implicit Euler; reduced:
//    one Newton iteration on the frozen tangent, 1 ms; full order: 10 ms as in navbench full)
//    under the first held-out load.
// memory_bytes: the reduced model's tables, or for a full-order model an estimate (its data
// arena, 12 bytes per factor entry, 17 doubles per element and 16 per node).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "bench_json.hpp"
#include "bench_tradeoff.hpp"
#include "nav/mesh/geometry.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "nav/tissue/newton_static.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "svg_plot.hpp"

namespace navbench {
namespace {

using nav::ReducedBasisSource;
using nav::ReducedForceKind;

/// A mesh with its scene, target node and loads.
struct Level {
  std::string name;
  nav::TetMesh mesh;
  nav::TissueScene scene;
  std::int32_t target = 0;
  std::vector<nav::TrainingLoad> held_out;
  nav::Snapshots training;
  std::vector<double> corotational_m;  ///< full-order corotational solutions, 3 n per held-out load
  std::vector<std::size_t> neo_loads;  ///< the held-out loads with a neo-Hookean reference
  std::vector<double> neo_hookean_m;   ///< 3 n per entry of neo_loads
};

/// One measured rung on one mesh.
struct Record {
  std::string mesh, model;
  int r = 0, sampled_elements = 0;
  std::int64_t tetrahedra = 0;
  double step_us_median = 0.0, step_us_p99 = 0.0;
  double error_rms_m = 0.0, error_max_m = 0.0, target_error_m = 0.0, error_rms_pct = 0.0;
  double error_rms_vs_corotational_m = 0.0, error_rms_vs_corotational_pct = 0.0, target_error_vs_corotational_m = 0.0;
  std::int64_t memory_bytes = 0;
};

/// A reduced rung: basis source, force reduction, r and the most cubature samples (1 where the
/// force reduction samples nothing).
struct ReducedCase {
  std::string model;
  ReducedBasisSource source;
  ReducedForceKind kind;
  int r, samples;
};

/// The generated liver's scene: attachments held, gravity along -z, tumour 3x stiffer, and a
/// diaphragm patch of 3 cm at the top.
nav::TissueScene embedded_scene(const nav::EmbeddedLiver& liver) {
  nav::TissueScene scene;
  scene.default_material = {5000.0, 0.45, 1060.0};
  scene.region_materials = {{static_cast<std::int32_t>(nav::TissueRegion::tumour), {15000.0, 0.45, 1060.0}}};
  scene.gravity_m_s2 = {0.0, 0.0, -9.81};
  scene.fixed_nodes = liver.attachment_nodes;
  return nav::with_diaphragm(liver.mesh, scene, 0.03);
}

std::int32_t nearest_node(const nav::TetMesh& mesh, const nav::Point3& p) {
  std::int32_t best = 0;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    if (nav::norm(nav::operator-(mesh.nodes_m[n], p)) <
        nav::norm(nav::operator-(mesh.nodes_m[static_cast<std::size_t>(best)], p)))
      best = static_cast<std::int32_t>(n);
  return best;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The held-out loads that get a neo-Hookean reference (its solve takes tens of seconds on
/// liverFine): the first of each kind.
bool is_reference_load(const nav::TrainingLoad& load) {
  return load.name.starts_with("gravity x") || load.name == "push 0" || load.name == "needle 0" ||
         load.name == "diaphragm 0";
}

/// Solves the level's training and held-out loads and the neo-Hookean references.
std::optional<std::string> prepare(Level& level) {
  const auto start = std::chrono::steady_clock::now();
  const nav::TrainingLoadOptions load_options;
  const auto training = nav::make_training_loads(level.mesh, level.scene, load_options, nav::LoadSet::training);
  level.held_out = nav::make_training_loads(level.mesh, level.scene, load_options, nav::LoadSet::held_out);
  auto snapshots = nav::solve_static_loads(level.mesh, level.scene, training);
  if (!snapshots.ok()) return "training: " + snapshots.error().describe();
  level.training = std::move(snapshots.value());
  nav::StaticSolveOptions full_load;
  full_load.snapshot_fractions = {1.0};
  auto corotational = nav::solve_static_loads(level.mesh, level.scene, level.held_out, full_load);
  if (!corotational.ok()) return "held-out loads: " + corotational.error().describe();
  level.corotational_m = std::move(corotational.value().displacements_m);
  const double full_s = seconds_since(start);
  nav::NewtonStaticOptions reference_options;
  reference_options.load_increments = 10;
  for (std::size_t k = 0; k < level.held_out.size(); ++k) {
    const nav::TrainingLoad& load = level.held_out[k];
    if (!is_reference_load(load)) continue;
    level.neo_loads.push_back(k);
    const auto reference = nav::solve_newton_static(level.mesh, nav::scene_for_load(level.scene, load),
                                                    load.inputs(1.0), {}, reference_options);
    if (!reference.ok()) return "neo-Hookean reference of " + load.name + ": " + reference.error().describe();
    const auto& x = reference.value().positions_m;
    for (std::size_t n = 0; n < level.mesh.nodes_m.size(); ++n)
      for (std::size_t c = 0; c < 3; ++c) level.neo_hookean_m.push_back(x[3 * n + c] - level.mesh.nodes_m[n][c]);
  }
  std::fprintf(
      stderr, "%s: %zu tets, %d training snapshots, %zu held-out loads; full-order solves %.1f s, neo-Hookean %.1f s\n",
      level.name.c_str(), level.mesh.tets.size(), level.training.count, level.held_out.size(), full_s,
      seconds_since(start) - full_s);
  return std::nullopt;
}

/// Fills the error fields of `record` from static solutions (3 n per held-out load): against
/// the neo-Hookean reference on its loads, against the full-order corotational model on all.
void score(const Level& level, const std::vector<double>& solutions_m, Record& record) {
  const std::size_t rows = 3 * level.mesh.nodes_m.size();
  const auto solution = [&](std::size_t k) { return std::span(solutions_m).subspan(k * rows, rows); };
  double sum_m2 = 0.0, sum_corot_m2 = 0.0;
  for (std::size_t j = 0; j < level.neo_loads.size(); ++j) {
    const auto neo = nav::displacement_error(solution(level.neo_loads[j]),
                                             std::span(level.neo_hookean_m).subspan(j * rows, rows), level.target);
    sum_m2 += neo.rms_m * neo.rms_m;
    record.error_max_m = std::max(record.error_max_m, neo.max_m);
    record.target_error_m = std::max(record.target_error_m, neo.target_m);
    record.error_rms_pct = std::max(record.error_rms_pct, 100.0 * neo.rms_m / neo.reference_max_m);
  }
  for (std::size_t k = 0; k < level.held_out.size(); ++k) {
    const auto corot =
        nav::displacement_error(solution(k), std::span(level.corotational_m).subspan(k * rows, rows), level.target);
    sum_corot_m2 += corot.rms_m * corot.rms_m;
    record.target_error_vs_corotational_m = std::max(record.target_error_vs_corotational_m, corot.target_m);
    record.error_rms_vs_corotational_pct =
        std::max(record.error_rms_vs_corotational_pct, 100.0 * corot.rms_m / corot.reference_max_m);
  }
  record.error_rms_m = std::sqrt(sum_m2 / static_cast<double>(level.neo_loads.size()));
  record.error_rms_vs_corotational_m = std::sqrt(sum_corot_m2 / static_cast<double>(level.held_out.size()));
}

/// Median and p99 of `steps` timed calls of `advance`.
void time_steps(int steps, const std::function<void()>& advance, Record& record) {
  std::vector<double> us;
  for (int s = 0; s < steps; ++s) {
    const auto start = std::chrono::steady_clock::now();
    advance();
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(us.begin(), us.end());
  record.step_us_median = us[us.size() / 2];
  record.step_us_p99 = us[std::min(us.size() - 1, us.size() * 99 / 100)];
}

/// A full-order rung: "linear", "corotational" or "stvk".
std::optional<Record> run_full_order(const Level& level, const std::string& model_name, bool quick) {
  nav::StaticSolveOptions statics;
  statics.snapshot_fractions = {1.0};
  nav::TissueSolverOptions realtime;
  realtime.rayleigh_mass_per_s = 40.0;
  realtime.cg_iterations = 1;
  if (model_name == "linear") {
    statics.solver.rotation = realtime.rotation = nav::ElementRotation::none;
  } else if (model_name == "stvk") {
    statics.solver.law = realtime.law = nav::ElementLaw::st_venant_kirchhoff;
    realtime.cg_iterations = 3;
  }
  Record record{level.name, model_name + "_full", 0, static_cast<int>(level.mesh.tets.size()),
                static_cast<std::int64_t>(level.mesh.tets.size())};
  const auto solved = nav::solve_static_loads(level.mesh, level.scene, level.held_out, statics);
  if (!solved.ok()) {
    std::fprintf(stderr, "  %s: %s\n", record.model.c_str(), solved.error().describe().c_str());
    return std::nullopt;
  }
  score(level, solved.value().displacements_m, record);
  const auto model =
      nav::make_tet_fem_model(level.mesh, nav::scene_for_load(level.scene, level.held_out[0]), realtime).value();
  auto data = nav::make_tet_fem_data(model).value();
  const nav::TissueInputs inputs = level.held_out[0].inputs(1.0);
  time_steps(
      quick ? 20 : 60, [&] { nav::step(model, data, inputs); }, record);
  record.memory_bytes = static_cast<std::int64_t>(data.arena.capacity_bytes()) + model.factor_bytes() +
                        17 * 8 * model.tet_count() + 16 * 8 * model.node_count();
  return record;
}

/// A reduced rung.
std::optional<Record> run_reduced(const Level& level, const ReducedCase& c, bool quick) {
  Record record{level.name, c.model, c.r, 0, static_cast<std::int64_t>(level.mesh.tets.size())};
  nav::ReductionOptions options;
  options.source = c.source;
  options.force_kind = c.kind;
  options.basis_size = c.r;
  options.max_cubature_samples = c.samples;
  const nav::TissueSolverOptions solver = nav::reduction_solver_options(c.kind);
  const auto& s = level.training;
  auto basis = c.source == ReducedBasisSource::pod
                   ? nav::make_pod_basis(level.mesh, level.scene, solver, options, s.displacements_m, s.count)
                   : nav::make_modal_basis(level.mesh, level.scene, solver, options);
  nav::Status reduced = basis.ok() ? nav::add_force_reduction(level.mesh, level.scene, solver, options,
                                                              s.displacements_m, s.count, basis.value())
                                   : nav::Status(basis.error());
  if (!reduced.ok()) {
    std::fprintf(stderr, "  %s r=%d: %s\n", c.model.c_str(), c.r, reduced.error().describe().c_str());
    return std::nullopt;
  }
  record.sampled_elements = static_cast<int>(basis.value().sample_tets.size());
  std::vector<double> solutions;
  for (const nav::TrainingLoad& load : level.held_out) {
    const auto u = nav::solve_reduced_static(level.mesh, level.scene, basis.value(), load);
    if (!u.ok()) {
      std::fprintf(stderr, "  %s r=%d: %s\n", c.model.c_str(), c.r, u.error().describe().c_str());
      return std::nullopt;
    }
    solutions.insert(solutions.end(), u.value().begin(), u.value().end());
  }
  score(level, solutions, record);
  const auto model = nav::make_reduced_model(level.mesh, nav::scene_for_load(level.scene, level.held_out[0]), solver,
                                             basis.value(), nav::ReducedSolverOptions{});
  if (!model.ok()) return std::nullopt;
  auto data = nav::make_reduced_data(model.value()).value();
  const nav::TissueInputs inputs = level.held_out[0].inputs(1.0);
  time_steps(
      quick ? 500 : 3000, [&] { nav::step(model.value(), data, inputs); }, record);
  record.memory_bytes = model.value().memory_bytes();
  return record;
}

/// The reduced rungs: POD with corotational cubature over r (POD stops at the snapshot count)
/// and over the cubature size at r = 16, and the other sources and force reductions at a few r.
std::vector<ReducedCase> reduced_cases(bool quick, int snapshot_count) {
  using S = ReducedBasisSource;
  using K = ReducedForceKind;
  if (quick)
    return {{"pod_corotational", S::pod, K::corotational_cubature, 4, 256},
            {"pod_corotational", S::pod, K::corotational_cubature, 16, 256},
            {"pod_linear", S::pod, K::linear, 8, 1},
            {"modes_linear", S::linear_modes, K::linear, 8, 1}};
  std::vector<ReducedCase> cases;
  for (int r : {1, 2, 4, 8, 16, 24, 32, 40})
    if (r <= snapshot_count) cases.push_back({"pod_corotational", S::pod, K::corotational_cubature, r, 256});
  for (int m : {16, 64}) cases.push_back({"pod_corotational", S::pod, K::corotational_cubature, 16, m});
  for (int r : {4, 16, 32}) cases.push_back({"pod_linear", S::pod, K::linear, r, 1});
  for (int r : {16, 32}) cases.push_back({"pod_stvk", S::pod, K::stvk_cubature, r, 256});
  for (int r : {8}) cases.push_back({"pod_stvk_cubic", S::pod, K::stvk_cubic_polynomial, r, 1});
  for (int r : {16, 64}) cases.push_back({"modes_corotational", S::linear_modes, K::corotational_cubature, r, 256});
  for (int r : {32}) cases.push_back({"modal_derivatives_stvk", S::modal_derivatives, K::stvk_cubature, r, 256});
  return cases;
}

navbench::Json to_json(const Record& r) {
  return {{"mesh", r.mesh},
          {"model", r.model},
          {"r", r.r},
          {"sampled_elements", r.sampled_elements},
          {"tetrahedra", r.tetrahedra},
          {"step_us_median", r.step_us_median},
          {"step_us_p99", r.step_us_p99},
          {"error_rms_m", r.error_rms_m},
          {"error_max_m", r.error_max_m},
          {"target_error_m", r.target_error_m},
          {"error_rms_pct", r.error_rms_pct},
          {"error_rms_vs_corotational_m", r.error_rms_vs_corotational_m},
          {"error_rms_vs_corotational_pct", r.error_rms_vs_corotational_pct},
          {"target_error_vs_corotational_m", r.target_error_vs_corotational_m},
          {"memory_bytes", r.memory_bytes}};
}

std::vector<Level> levels(bool quick) {
  std::vector<Level> out;
  const std::vector<std::pair<std::string, int>> livers =
      quick ? std::vector<std::pair<std::string, int>>{{"liver_1k", 1000}}
            : std::vector<std::pair<std::string, int>>{{"liverFine", 22019}};
  for (const auto& [name, tets] : livers) {
    auto mesh = nav::load_liver_mesh(NAV_SHARED_LIVER_DIR, tets);
    if (!mesh.ok()) {
      std::fprintf(stderr, "%s: %s\n", name.c_str(), mesh.error().describe().c_str());
      continue;
    }
    Level level{name, std::move(mesh.value()), {}, 0, {}, {}, {}, {}, {}};
    level.scene = nav::liver_reduction_scene(level.mesh);
    level.target = nav::central_target_node(level.mesh);
    out.push_back(std::move(level));
  }
  if (!quick) {
    nav::EmbeddedLiver liver = nav::make_embedded_liver(nav::kEmbeddedLiverElementSizeM);
    Level level{"generated_liver",
                liver.mesh,
                embedded_scene(liver),
                nearest_node(liver.mesh, liver.tumour_centre_m),
                {},
                {},
                {},
                {},
                {}};
    out.push_back(std::move(level));
  }
  return out;
}

/// Writes the records so far as JSON and as the plot (after every mesh, so that a long run
/// leaves its finished meshes behind); false if a file cannot be written.
bool write_outputs(const std::vector<Record>& records, const std::string& json_path, const std::string& plot_path) {
  std::vector<navbench::Json> json;
  for (const Record& r : records) json.push_back(to_json(r));
  std::vector<PlotPoint> points;
  for (const Record& r : records)
    points.push_back(
        {std::max(r.step_us_median, 1e-3), std::max(r.error_rms_m, 1e-9), r.model, r.mesh,
         r.mesh + " " + r.model + " r=" + std::to_string(r.r) + " m=" + std::to_string(r.sampled_elements)});
  const std::string svg =
      log_log_svg(points, {"median step time (us, log)", "RMS nodal error vs neo-Hookean on held-out loads (m, log)",
                           "Tissue rungs: error against step time"});
  return navbench::write_json_records(json_path, json) && navbench::write_output(plot_path, svg);
}

}  // namespace

int run_tradeoff_bench(const std::vector<std::string>& args) {
  constexpr const char* kUsage = "usage: navbench tradeoff --json FILE --plot FILE.svg [--quick]\n";
  const auto parsed = parse_bench_args(args, kUsage);
  if (!parsed) return 2;
  std::string plot_path;
  for (std::size_t k = 0; k + 1 < args.size(); ++k)
    if (args[k] == "--plot") plot_path = args[k + 1];
  if (plot_path.empty()) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  std::vector<Record> records;
  for (Level& level : levels(parsed->quick)) {
    if (const auto failure = prepare(level)) {
      std::fprintf(stderr, "%s: %s\n", level.name.c_str(), failure->c_str());
      return 1;
    }
    const auto add = [&](const std::optional<Record>& record) {
      if (!record) return;
      records.push_back(*record);
      const Record& r = records.back();
      std::fprintf(
          stderr,
          "  %-24s r %3d m %4d  %9.2f us (p99 %9.2f)  rms %.3e m (%.2f %%; vs corot %.2f %%)  target %.3f mm  %lld B\n",
          r.model.c_str(), r.r, r.sampled_elements, r.step_us_median, r.step_us_p99, r.error_rms_m, r.error_rms_pct,
          r.error_rms_vs_corotational_pct, 1e3 * r.target_error_m, static_cast<long long>(r.memory_bytes));
    };
    for (const char* model : {"linear", "corotational", "stvk"})
      if (!parsed->quick || std::string(model) != "stvk") add(run_full_order(level, model, parsed->quick));
    for (const ReducedCase& c : reduced_cases(parsed->quick, level.training.count))
      add(run_reduced(level, c, parsed->quick));
    if (!write_outputs(records, parsed->json_path, plot_path)) return 1;
  }
  return 0;
}

}  // namespace navbench
