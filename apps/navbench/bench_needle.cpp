// navbench needle: median and p99 step times of the needle alone (20, 30, 40 elements), of
// the needle with 8, 16 and 32 path constraints (30 elements; 32 also at 20 elements), of the
// needle (20, 30, 40 elements) with 8, 16 and 32 path points in the reduced liver (r = 16,
// tissue every tick; 32 points once per instruction set of the Gauss-Seidel kernels, every
// element count and kernel set in alternating turns, first), and of the needle coupled to the
// full-order corotational embedded liver (about 5k tetrahedra) with the tissue stepping every
// tick or every 10 ticks; and the force profile of an insertion-retraction cycle against depth
// with its stiffness, cutting and friction parts, as an SVG next to the JSON.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "bench_json.hpp"
#include "bench_needle.hpp"
#include "nav/needle/tissue_coupling.hpp"

namespace {

using namespace navbench::needle_scenes;

struct Record {
  std::string name;
  int elements = 0, constraint_points = 0, rows = 0;
  long long tets = 0;
  int needle_steps_per_tissue_step = 0;
  double median_us = 0.0, p99_us = 0.0, residual_m = 0.0;
  int basis_size = 0;                                         ///< r of a reduced tissue, 0 otherwise
  nav::KernelIsa kernel_isa = nav::KernelIsa::best;           ///< of the Gauss-Seidel lane kernels (resolved)
  int sweeps = nav::NeedleTissueScene{}.gauss_seidel_sweeps;  ///< of projected Gauss-Seidel, 0 without constraints
};

/// Appends the times of `count` calls of `tick` (given the tick index, from `first`) to `us`, in microseconds.
void time_ticks_into(std::vector<double>& us, int first, int count, const std::function<void(int)>& tick) {
  for (int k = first; k < first + count; ++k) {
    const auto start = std::chrono::steady_clock::now();
    tick(k);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
  }
}

/// (median, p99) of step times.
std::pair<double, double> median_p99(std::vector<double> us) {
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[std::min(us.size() - 1, us.size() * 99 / 100)]};
}

/// Times `ticks` calls of `tick` (given the tick index); returns (median, p99) in microseconds.
std::pair<double, double> time_ticks(int ticks, const std::function<void(int)>& tick) {
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(ticks));
  time_ticks_into(us, 0, ticks, tick);
  return median_p99(std::move(us));
}

/// Base position of a back-and-forth motion of +-0.2 mm around x0 in 20 um steps.
double oscillating_x_m(double x0_m, int tick) {
  const int phase = tick % 40;
  return x0_m + 2e-5 * (phase < 20 ? phase - 10 : 30 - phase);
}

Record needle_alone(int elements, int ticks) {
  const nav::NeedleModel model = nav::make_needle_model(needle(elements)).value();
  nav::NeedleData data = nav::make_needle_data(model, {}).value();
  nav::NeedleInputs inputs;
  inputs.tip_force_n = {0.0, 0.05, 0.0};
  const auto [median, p99] = time_ticks(ticks, [&](int k) {
    inputs.base.position_m = {oscillating_x_m(0.0, k), 0.0, 0.0};
    nav::step(model, data, inputs);
  });
  return {"needle_alone",       elements, 0, 0, 0, 0, median, p99, 0.0, 0,
          nav::KernelIsa::best, 0};  // no constraints: no sweeps
}

Record needle_with_constraints(int elements, int points, int ticks) {
  const double spacing_m = 0.004;
  const nav::NeedleTissueModel model =
      nav::make_needle_tissue_model(needle(elements), capsule_and_parenchyma(spacing_m)).value();
  nav::NeedleTissueData data = nav::make_needle_tissue_data(model, {}).value();
  // The tip starts 5 mm off the capsule: insert until `points` path points hold the shaft.
  double x = 0.0;
  while (data.report.active_path_points < points) drive_base_to(model, data, x += 1e-3);
  nav::NeedleTissueInputs inputs;
  int rows = 0;
  double residual_m = 0.0;
  const auto [median, p99] = time_ticks(ticks, [&](int k) {
    inputs.needle.base.position_m = {oscillating_x_m(x, k), 1e-3 * std::sin(1e-2 * k), 0.0};
    nav::step(model, data, inputs);
    rows = std::max(rows, data.row_count);
    residual_m = std::max(residual_m, data.report.residual_m);
  });
  return {"needle_constraints", elements, data.report.active_path_points, rows, 0, 0, median, p99, residual_m, 0};
}

/// The embedded liver's full-order corotational model, quasi-static.
nav::TetFemModel full_order_liver(const EmbeddedLiverScene& liver) {
  nav::TissueSolverOptions options;
  options.integrator = nav::Integrator::quasi_static;
  options.cg_iterations = 2;
  return nav::make_tet_fem_model(liver.liver.mesh, liver.scene(), options).value();
}

Record coupled(const EmbeddedLiverScene& liver, const nav::TetFemModel& tissue, int ratio, int ticks) {
  const Approach approach = approach_tumour(liver);
  const nav::CoupledNeedleModel model =
      nav::make_coupled_needle_model(needle(30), liver_capsule(approach, 0.01), tissue, 64, ratio).value();
  std::fprintf(stderr, "  liver compliance at the entry: %.2e m/N (normal %.2e), correlation length %.1f mm\n",
               model.interaction.scene.point_compliance_m_per_n,
               approach.direction.dot(model.interaction.compliance_tensor_m_per_n * approach.direction),
               1e3 * model.interaction.scene.compliance_correlation_length_m);
  nav::CoupledNeedleData data = nav::make_coupled_needle_data(model, approach.base_at(0.0)).value();
  nav::NeedleInputs inputs;
  int rows = 0;
  const auto [median, p99] = time_ticks(ticks, [&](int k) {
    inputs.base = approach.base_at(2e-5 * (k + 1));
    nav::step(model, data, inputs);
    rows = std::max(rows, data.interaction.row_count);
  });
  std::fprintf(stderr, "  coupled 1:%d: punctures %d, path points %d, tip depth %.1f mm, health bits %u (tissue %u)\n",
               ratio, data.interaction.report.punctures, data.interaction.report.active_path_points,
               1e3 * data.interaction.report.tip_depth_m, data.interaction.health.bits(), data.tissue.health.bits());
  return {"coupled_full_order_corotational",
          30,
          data.interaction.report.active_path_points,
          rows,
          static_cast<long long>(liver.liver.mesh.tets.size()),
          ratio,
          median,
          p99,
          data.interaction.report.residual_m,
          0};
}

/// The needle in the reduced liver, the tissue stepping every tick, its Gauss-Seidel kernels
/// of `isa`: inserted towards the tumour until `points` path points hold the shaft, then
/// ticked while the base moves back and forth along the shaft and sideways (as
/// needle_with_constraints).
struct ReducedRun {
  int elements = 0;
  Approach approach;
  nav::ReducedCoupledNeedleModel model;
  nav::ReducedCoupledNeedleData data;
  double advanced_m = 0.0;
  int rows = 0;
  double residual_m = 0.0;
  std::vector<double> us;  ///< step times

  ReducedRun(const EmbeddedLiverScene& liver, const nav::ReducedModel& tissue, int elements, int points,
             nav::KernelIsa isa, int sweeps = nav::NeedleTissueScene{}.gauss_seidel_sweeps)
      : elements(elements),
        approach(approach_tumour(liver)),
        model(nav::make_coupled_needle_model(needle(elements), scene_of(approach, isa, sweeps), tissue,
                                             liver.liver.mesh, 64, 1)
                  .value()),
        data(nav::make_coupled_needle_data(model, approach.base_at(0.0)).value()),
        advanced_m(insert_until(model, data, approach, points)) {}

  static nav::NeedleTissueScene scene_of(const Approach& approach, nav::KernelIsa isa, int sweeps) {
    nav::NeedleTissueScene scene = liver_capsule(approach, kReducedPathSpacingM);
    scene.kernel_isa = isa;
    scene.gauss_seidel_sweeps = sweeps;
    return scene;
  }

  /// Times ticks [first, first + count).
  void time(int first, int count) {
    time_ticks_into(us, first, count, [&](int k) {
      nav::step(model, data, nav::NeedleInputs{approach.wobbled_base(advanced_m, k), {}, {}});
      rows = std::max(rows, data.interaction.row_count);
      residual_m = std::max(residual_m, data.interaction.report.residual_m);
    });
  }

  Record record(const EmbeddedLiverScene& liver, const nav::ReducedModel& tissue) const {
    std::fprintf(
        stderr,
        "  reduced liver, %d elements, %s kernels: inserted %.1f mm, path points %d, health bits %u (tissue %u)\n",
        elements, std::string(nav::kernel_isa_name(model.interaction.scene.kernel_isa)).c_str(), 1e3 * advanced_m,
        data.interaction.report.active_path_points, data.interaction.health.bits(), data.tissue.health.bits());
    const auto [median, p99] = median_p99(us);
    return {"coupled_reduced_liver",
            elements,
            data.interaction.report.active_path_points,
            rows,
            static_cast<long long>(liver.liver.mesh.tets.size()),
            1,
            median,
            p99,
            residual_m,
            tissue.basis_size(),
            nav::resolve_kernel_isa(model.interaction.scene.kernel_isa),
            model.interaction.scene.gauss_seidel_sweeps};
  }
};

Record coupled_reduced(const EmbeddedLiverScene& liver, const nav::ReducedModel& tissue, int elements, int points,
                       int ticks) {
  ReducedRun run(liver, tissue, elements, points, nav::KernelIsa::best);
  run.time(0, ticks);
  return run.record(liver, tissue);
}

/// Sweeps at which the 32-point liver case reaches a smaller largest residual than the
/// default's 30 sweeps did in row order (3.9 against 5.3 um).
constexpr int kFewSweeps = 10;

/// 32 path points at each of `element_counts`, once per available instruction set of the
/// Gauss-Seidel kernels (the same bits) and with the best one at kFewSweeps: every case timed
/// with the others in turns of 500 ticks, so that a shared host's slow spells fall on all
/// alike, the element counts included. Records by element count, then as listed here.
std::vector<Record> coupled_reduced_per_isa(const EmbeddedLiverScene& liver, const nav::ReducedModel& tissue,
                                            std::initializer_list<int> element_counts, int ticks) {
  std::vector<std::unique_ptr<ReducedRun>> runs;
  for (int elements : element_counts) {
    for (nav::KernelIsa isa : {nav::KernelIsa::baseline, nav::KernelIsa::avx2, nav::KernelIsa::avx512})
      if (nav::kernel_isa_available(isa))
        runs.push_back(std::make_unique<ReducedRun>(liver, tissue, elements, 32, isa));
    runs.push_back(std::make_unique<ReducedRun>(liver, tissue, elements, 32, nav::KernelIsa::best, kFewSweeps));
  }
  constexpr int kTurn = 500;
  for (int first = 0; first < ticks; first += kTurn)
    for (auto& run : runs) run->time(first, std::min(kTurn, ticks - first));
  std::vector<Record> records;
  for (const auto& run : runs) records.push_back(run->record(liver, tissue));
  return records;
}

/// One point of the force profile.
struct ProfilePoint {
  double depth_mm;
  nav::InsertionForces forces;
};

/// Insert 40 mm, hold, retract 10 mm, re-insert 15 mm, retract fully.
std::vector<ProfilePoint> insertion_profile() {
  const nav::NeedleTissueModel model = nav::make_needle_tissue_model(needle(30), capsule_and_parenchyma(0.005)).value();
  nav::NeedleTissueData data = nav::make_needle_tissue_data(model, {}).value();
  std::vector<ProfilePoint> profile;
  nav::NeedleTissueInputs inputs;
  double x = 0.0;
  for (double target : {0.045, 0.045, 0.035, 0.05, -0.005}) {
    for (int k = 0; k < 300 || std::abs(target - x) > 1e-12; ++k) {
      x += std::max(-2e-5, std::min(2e-5, target - x));
      inputs.needle.base.position_m = {x, 0.0, 0.0};
      nav::step(model, data, inputs);
      if (k % 5 == 0) profile.push_back({1e3 * data.report.tip_depth_m, data.report.forces});
    }
  }
  return profile;
}

void write_profile_svg(const std::string& path, const std::vector<ProfilePoint>& profile) {
  std::FILE* file = navbench::open_bench_output(path);
  if (!file) return;
  const double width = 900, height = 560, left = 70, right = 170, top = 30, bottom = 60;
  const double x_lo = -6.0, x_hi = 46.0, y_lo = -1.2, y_hi = 1.4;
  const auto px = [&](double mm) { return left + (mm - x_lo) / (x_hi - x_lo) * (width - left - right); };
  const auto py = [&](double n) { return top + (y_hi - n) / (y_hi - y_lo) * (height - top - bottom); };
  std::fprintf(file,
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" "
               "font-size=\"12\">\n",
               width, height);
  std::fprintf(file, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
  for (int mm = 0; mm <= 45; mm += 5)
    std::fprintf(file,
                 "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
                 "text-anchor=\"middle\">%d</text>\n",
                 px(mm), top, px(mm), height - bottom, px(mm), height - bottom + 16, mm);
  for (int k = -12; k <= 14; k += 2) {
    const double n = 0.1 * k;
    std::fprintf(file,
                 "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/><text x=\"%.1f\" y=\"%.1f\" "
                 "text-anchor=\"end\">%.1f</text>\n",
                 left, py(n), width - right, py(n), k == 0 ? "#888" : "#ddd", left - 6, py(n) + 4, n);
  }
  std::fprintf(file, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">tip depth below the capsule (mm)</text>\n",
               (left + width - right) / 2, height - 20);
  std::fprintf(file,
               "<text x=\"16\" y=\"%.1f\" transform=\"rotate(-90 16 %.1f)\" text-anchor=\"middle\">force resisting "
               "insertion (N)</text>\n",
               (top + height - bottom) / 2, (top + height - bottom) / 2);
  const char* names[] = {"total", "stiffness (capsule)", "cutting", "shaft friction"};
  const char* colours[] = {"#000000", "#1f77b4", "#d62728", "#2ca02c"};
  for (int series = 0; series < 4; ++series) {
    std::fprintf(file, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"%s\" points=\"", colours[series],
                 series == 0 ? "2" : "1.2");
    for (const ProfilePoint& p : profile) {
      const double values[] = {p.forces.total_n, p.forces.stiffness_n, p.forces.cutting_n, p.forces.friction_n};
      std::fprintf(file, "%.1f,%.1f ", px(std::clamp(p.depth_mm, x_lo, x_hi)),
                   py(std::clamp(values[series], y_lo, y_hi)));
    }
    std::fprintf(file,
                 "\"/>\n<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\"/><text "
                 "x=\"%.1f\" y=\"%.1f\">%s</text>\n",
                 width - right + 12, top + 20 + 20.0 * series, width - right + 32, top + 20 + 20.0 * series,
                 colours[series], width - right + 38, top + 24 + 20.0 * series, names[series]);
  }
  std::fprintf(file,
               "<text x=\"%.1f\" y=\"%.1f\">insert 40 mm, hold, retract 10,</text><text x=\"%.1f\" "
               "y=\"%.1f\">re-insert 15, retract all</text>\n</svg>\n",
               width - right + 12, top + 120, width - right + 12, top + 136);
  std::fclose(file);
}

bool write_json(const std::string& path, const std::vector<Record>& records) {
  std::vector<navbench::Json> json;
  for (const Record& r : records)
    json.push_back({{"case", r.name},
                    {"elements", r.elements},
                    {"constraint_points", r.constraint_points},
                    {"rows", r.rows},
                    {"tetrahedra", r.tets},
                    {"needle_steps_per_tissue_step", r.needle_steps_per_tissue_step},
                    {"basis_size", r.basis_size},
                    {"kernel_isa", std::string(nav::kernel_isa_name(nav::resolve_kernel_isa(r.kernel_isa)))},
                    {"step_us_median", r.median_us},
                    {"gauss_seidel_sweeps", r.sweeps},
                    {"step_us_p99", r.p99_us},
                    {"residual_m", r.residual_m}});
  return navbench::write_json_records(path, json);
}

}  // namespace

namespace navbench {

int run_needle_bench(const std::vector<std::string>& args) {
  const auto parsed = parse_bench_args(args, "usage: navbench needle --json FILE [--quick]\n");
  if (!parsed) return 2;
  const std::string& json_path = parsed->json_path;
  const bool quick = parsed->quick;
  const int ticks = quick ? 500 : 20000;
  // The 32-point cases in the reduced liver first: timed together, and before the host has
  // run the other cases for minutes.
  const EmbeddedLiverScene liver;
  const nav::ReducedModel reduced = reduced_liver(liver);
  const std::vector<Record> with_32_points = coupled_reduced_per_isa(liver, reduced, {20, 30, 40}, ticks);
  std::vector<Record> records;
  for (int elements : {20, 30, 40}) records.push_back(needle_alone(elements, ticks));
  for (int points : {8, 16, 32}) records.push_back(needle_with_constraints(30, points, ticks));
  records.push_back(needle_with_constraints(20, 32, ticks));
  const nav::TetFemModel full = full_order_liver(liver);
  for (int ratio : {1, 10}) records.push_back(coupled(liver, full, ratio, quick ? 600 : 2000));
  for (int elements : {20, 30, 40}) {
    for (int points : {8, 16}) records.push_back(coupled_reduced(liver, reduced, elements, points, ticks));
    for (const Record& r : with_32_points)
      if (r.elements == elements) records.push_back(r);
  }
  for (const Record& r : records)
    std::fprintf(stderr,
                 "%-32s %2d elements %2d points %3d rows %5lld tets 1:%-2d %-8s %2d sweeps median %9.1f us  p99 %9.1f "
                 "us  residual %.1e m\n",
                 r.name.c_str(), r.elements, r.constraint_points, r.rows, r.tets, r.needle_steps_per_tissue_step,
                 std::string(nav::kernel_isa_name(nav::resolve_kernel_isa(r.kernel_isa))).c_str(), r.sweeps,
                 r.median_us, r.p99_us, r.residual_m);
  if (!write_json(json_path, records)) return 1;
  const std::size_t dot = json_path.rfind('.');
  write_profile_svg((dot == std::string::npos ? json_path : json_path.substr(0, dot)) + "_force_profile.svg",
                    insertion_profile());
  return 0;
}

}  // namespace navbench
