// navbench connective: see bench_connective.hpp.
#include "bench_connective.hpp"
#include "bench_json.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "bench_args.hpp"
#include "nav/connective/organ_ligaments.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace {

/// One JSON record: a case, its sizes and what was measured (NaN fields are left out).
struct Record {
  std::string name;
  std::string solver;
  long long frames = 0, points = 0, pairs = 0, tets = 0;
  double youngs_modulus_pa = NAN, median_us = NAN, p99_us = NAN, largest_displacement_m = NAN, difference_max_m = NAN,
         difference_rms_m = NAN, spring_n_m = NAN;
  int stable = -1;
  unsigned health = 0;
};

/// Times `count` calls of `tick`; returns (median, p99) in microseconds.
std::pair<double, double> time_ticks(int count, const std::function<void(int)>& tick) {
  std::vector<double> us;
  for (int k = 0; k < count; ++k) {
    const auto start = std::chrono::steady_clock::now();
    tick(k);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[std::min(us.size() - 1, us.size() * 99 / 100)]};
}

/// A ligament block of n x n x m frames (1 cm apart), top fixed, bottom driven sideways.
Record sweep_case(int n, int m, int points_per_axis, nav::FrameSolver solver, int steps) {
  nav::FrameGrid grid;
  grid.counts = {n, n, m};
  grid.spacing_m = {0.01, 0.01, 0.01};
  grid.points_per_cell_axis = points_per_axis;
  nav::FrameTissueScene scene;
  scene.layout = nav::make_grid_layout(grid).value();
  scene.material = {1e5, 0.45, 1100.0};
  for (std::size_t f = 0; f < scene.layout.frames_m.size(); ++f) {
    if (scene.layout.frames_m[f][2] == 0.0) scene.supports.driven_frames.push_back(static_cast<std::int32_t>(f));
    if (scene.layout.frames_m[f][2] > 0.01 * (m - 1) - 1e-9)
      scene.supports.fixed_frames.push_back(static_cast<std::int32_t>(f));
  }
  nav::FrameTissueOptions options;
  options.solver = solver;
  options.rayleigh_mass_per_s = 1.0;
  const nav::FrameTissueModel model = nav::make_frame_tissue_model(scene, options).value();
  nav::FrameTissueData data = nav::make_frame_tissue_data(model).value();
  std::vector<double> driven(3 * model.driven_frames().size());
  const auto [median, p99] = time_ticks(steps, [&](int k) {
    for (std::size_t d = 0; d < model.driven_frames().size(); ++d)
      for (std::size_t a = 0; a < 3; ++a)
        driven[3 * d + a] = model.rest_positions_m()[3 * static_cast<std::size_t>(model.driven_frames()[d]) + a] +
                            (a == 0 ? 0.003 * std::sin(0.1 * k) : 0.0);
    nav::FrameTissueInputs inputs;
    inputs.driven_positions_m = driven;
    nav::step(model, data, inputs);
  });
  Record r;
  r.name = "frames_sweep";
  r.solver = solver == nav::FrameSolver::cg_block_jacobi ? "cg60_block_jacobi" : "banded_cholesky";
  r.frames = model.frame_count();
  r.points = model.point_count();
  r.pairs = model.pair_count();
  r.median_us = median;
  r.p99_us = p99;
  r.health = data.health.bits();
  return r;
}

/// The two ligaments of the liver scene: 3 x 3 cm blocks, 3 cm long, over the right lobe and
/// left of the falciform plane.
std::vector<nav::LigamentSpec> two_ligaments() {
  std::vector<nav::LigamentSpec> specs(2);
  specs[0].footprint_centre_m = {-0.045, 0.0, 0.0};
  specs[1].footprint_centre_m = {0.035, 0.015, 0.0};
  for (nav::LigamentSpec& spec : specs) spec.embed_m = 0.006;
  return specs;
}

nav::TetFemModel liver_model(const nav::TetMesh& mesh, const nav::OrganAttachment& attachment, bool fixed) {
  nav::TissueScene scene;
  scene.default_material = {5000.0, 0.45, 1060.0};
  scene.gravity_m_s2 = {0.0, 0.0, -9.81};
  if (fixed)
    scene.fixed_nodes = attachment.nodes;
  else
    nav::declare_attachment(attachment, scene);
  nav::TissueSolverOptions options;
  options.cg_iterations = 5;
  options.rayleigh_mass_per_s = 2.0;
  return nav::make_tet_fem_model(mesh, scene, options).value();
}

/// The liver under gravity for `steps` steps of 10 ms, held by the ligaments (when given) or
/// by fixed nodes at their attachment; the step times and final displacements.
struct LiverRun {
  double median_us = 0.0, p99_us = 0.0;
  std::vector<double> displacement_m;
  unsigned health = 0;
};

LiverRun run_liver(const nav::TetMesh& mesh, const nav::OrganLigaments& ligaments, bool with_ligaments, int steps) {
  const nav::TetFemModel model = liver_model(mesh, ligaments.attachment, !with_ligaments);
  nav::TetFemData data = nav::make_tet_fem_data(model).value();
  nav::FrameTissueData ligament = nav::make_frame_tissue_data(ligaments.model).value();
  nav::AttachmentBuffers buffers = nav::make_attachment_buffers(ligaments.attachment);
  nav::TissueInputs inputs;
  LiverRun run;
  std::tie(run.median_us, run.p99_us) = time_ticks(steps, [&](int) {
    if (with_ligaments) {
      nav::step_attached(ligaments.model, ligament, ligaments.attachment, buffers, data.positions_m, 1.0);
      inputs.point_forces = buffers.point_forces;
    }
    nav::step(model, data, inputs);
  });
  for (std::size_t i = 0; i < data.positions_m.size(); ++i)
    run.displacement_m.push_back(data.positions_m[i] - model.rest_positions_m()[i]);
  run.health = data.health.bits() | (with_ligaments ? ligament.health.bits() : 0u);
  return run;
}

double largest(const std::vector<double>& values) {
  double m = 0.0;
  for (double v : values) m = std::isfinite(v) ? std::max(m, std::abs(v)) : INFINITY;
  return m;
}

nav::OrganLigaments make_ligaments(const nav::TetMesh& mesh, double youngs_modulus_pa, bool stabilise) {
  nav::FrameTissueOptions options;
  options.rayleigh_mass_per_s = 1.0;
  return nav::make_organ_ligaments(mesh, two_ligaments(), {youngs_modulus_pa, 0.45, 1100.0}, options, {0.0, 0.0, -9.81},
                                   stabilise)
      .value();
}

/// Liver held by two ligaments against fixed nodes: cost and displacement difference.
std::vector<Record> liver_cases(const nav::TetMesh& mesh, int steps) {
  std::vector<Record> records;
  const nav::OrganLigaments ligaments = make_ligaments(mesh, 1e6, true);
  const LiverRun fixed = run_liver(mesh, ligaments, false, steps), held = run_liver(mesh, ligaments, true, steps);
  double max_m = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < fixed.displacement_m.size(); ++i) {
    const double d = held.displacement_m[i] - fixed.displacement_m[i];
    max_m = std::max(max_m, std::abs(d));
    sum2 += d * d;
  }
  Record f;
  f.name = "liver_fixed_nodes";
  f.tets = static_cast<long long>(mesh.tets.size());
  f.median_us = fixed.median_us;
  f.p99_us = fixed.p99_us;
  f.largest_displacement_m = largest(fixed.displacement_m);
  f.health = fixed.health;
  Record h = f;
  h.name = "liver_two_ligaments";
  h.solver = "cg60_block_jacobi";
  h.frames = ligaments.model.frame_count();
  h.points = ligaments.model.point_count();
  h.pairs = ligaments.model.pair_count();
  h.youngs_modulus_pa = 1e6;
  h.median_us = held.median_us;
  h.p99_us = held.p99_us;
  h.largest_displacement_m = largest(held.displacement_m);
  h.difference_max_m = max_m;
  h.difference_rms_m = std::sqrt(sum2 / static_cast<double>(fixed.displacement_m.size() / 3));
  h.spring_n_m = ligaments.attachment.spring_stiffness_n_m;
  h.health = held.health;
  records.push_back(f);
  records.push_back(h);
  return records;
}

/// Whether the staggered coupling stays bounded (finite, under 10 cm) over `steps` steps.
std::vector<Record> stability_cases(const nav::TetMesh& mesh, int steps, const std::vector<double>& moduli_pa) {
  std::vector<Record> records;
  for (bool stabilise : {false, true})
    for (double modulus_pa : moduli_pa) {
      const nav::OrganLigaments ligaments = make_ligaments(mesh, modulus_pa, stabilise);
      const LiverRun run = run_liver(mesh, ligaments, true, steps);
      Record r;
      r.name = stabilise ? "coupling_stabilised" : "coupling_plain_staggered";
      r.youngs_modulus_pa = modulus_pa;
      r.largest_displacement_m = largest(run.displacement_m);
      r.stable =
          r.largest_displacement_m < 0.1 && (run.health & static_cast<unsigned>(nav::HealthFlag::non_finite_state)) == 0
              ? 1
              : 0;
      r.spring_n_m = ligaments.attachment.spring_stiffness_n_m;
      r.health = run.health;
      records.push_back(r);
    }
  return records;
}

bool write_json(const std::string& path, const std::vector<Record>& records) {
  std::vector<navbench::Json> json;
  for (const Record& r : records) {
    navbench::Json record = {{"case", r.name}};
    if (!r.solver.empty()) record["solver"] = r.solver;
    if (r.frames > 0) {
      record["frames"] = r.frames;
      record["points"] = r.points;
      record["pairs"] = r.pairs;
    }
    if (r.tets > 0) record["tetrahedra"] = r.tets;
    const std::pair<const char*, double> numbers[] = {{"youngs_modulus_pa", r.youngs_modulus_pa},
                                                      {"step_us_median", r.median_us},
                                                      {"step_us_p99", r.p99_us},
                                                      {"largest_displacement_m", r.largest_displacement_m},
                                                      {"difference_max_m", r.difference_max_m},
                                                      {"difference_rms_m", r.difference_rms_m},
                                                      {"stabilising_spring_n_m", r.spring_n_m}};
    for (const auto& [key, value] : numbers)
      if (std::isfinite(value)) record[key] = value;
    if (r.stable >= 0) record["stable"] = r.stable == 1;
    record["health"] = r.health;
    json.push_back(std::move(record));
  }
  return navbench::write_json_records(path, json);
}

}  // namespace

namespace navbench {

int run_connective_bench(const std::vector<std::string>& args) {
  const auto parsed = parse_bench_args(args, "usage: navbench connective --json FILE [--quick]\n");
  if (!parsed) return 2;
  const bool quick = parsed->quick;
  std::vector<Record> records;
  const int sweep_steps = quick ? 20 : 300;
  for (const auto& [n, m] : std::vector<std::pair<int, int>>{{3, 3}, {4, 4}, {5, 5}, {6, 8}})
    for (int points : {2, 3}) {
      if (quick && (n > 4 || points > 2)) continue;
      records.push_back(sweep_case(n, m, points, nav::FrameSolver::cg_block_jacobi, sweep_steps));
      if (n <= 4) records.push_back(sweep_case(n, m, points, nav::FrameSolver::banded_cholesky, sweep_steps));
    }
  const nav::EmbeddedLiver liver = nav::make_embedded_liver(nav::kEmbeddedLiverElementSizeM);
  for (const Record& r : liver_cases(liver.mesh, quick ? 20 : 300)) records.push_back(r);
  const std::vector<double> moduli =
      quick ? std::vector<double>{1e4, 1e6} : std::vector<double>{1e3, 1e4, 3e4, 1e5, 2e5, 1e6, 1e7};
  for (const Record& r : stability_cases(liver.mesh, quick ? 20 : 200, moduli)) records.push_back(r);
  for (const Record& r : records)
    std::fprintf(stderr,
                 "%-26s %-18s %4lld frames %5lld points %5lld tets  E %8.1e  median %9.1f us  p99 %9.1f us  largest "
                 "%.4f m  diff %.4f m  stable %d  health %u\n",
                 r.name.c_str(), r.solver.c_str(), r.frames, r.points, r.tets, r.youngs_modulus_pa, r.median_us,
                 r.p99_us, r.largest_displacement_m, r.difference_max_m, r.stable, r.health);
  if (!write_json(parsed->json_path, records)) return 1;
  return 0;
}

}  // namespace navbench
