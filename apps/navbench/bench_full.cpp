// navbench full: step time and error of every full-order tissue model on liver meshes of
// about 1k, 5k and 22k elements, against the neo-Hookean reference on two scenes (gravity; a
// probe pressing 2 cm), written as JSON records plus an SVG plot of error against step time.
// --quick runs the 1k mesh only (for ctest); the full run takes some minutes.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "bench_full.hpp"
#include "bench_json.hpp"
#include "nav/mesh/geometry.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "nav/tissue/mass_spring_model.hpp"
#include "nav/tissue/newton_static.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace {

using nav::ElementLaw;
using nav::ElementRotation;
using nav::Integrator;

/// Simulated time each model gets to settle, in seconds, and its mass damping.
constexpr double kSettleS = 1.0;
constexpr double kDampingPerS = 40.0;

/// A real-time model under test.
struct Case {
  std::string model, integrator;
  nav::TissueSolverOptions options;  ///< unused by the mass-spring model
  bool mass_spring = false;
};

std::vector<Case> cases() {
  std::vector<Case> all;
  const auto fem = [&](const char* model, const char* integrator, ElementLaw law, ElementRotation rotation,
                       Integrator scheme, double gain_pa, int cg_iterations) {
    nav::TissueSolverOptions o;
    o.law = law;
    o.rotation = rotation;
    o.integrator = scheme;
    o.incompressibility_gain_pa = gain_pa;
    o.cg_iterations = cg_iterations;
    o.rayleigh_mass_per_s = kDampingPerS;
    all.push_back({model, integrator, o, false});
  };
  fem("linear", "implicit_euler", ElementLaw::linear_elastic, ElementRotation::none, Integrator::implicit_euler, 0.0,
      1);
  fem("linear", "explicit_central_difference", ElementLaw::linear_elastic, ElementRotation::none,
      Integrator::explicit_central_difference, 0.0, 1);
  fem("corotational", "implicit_euler", ElementLaw::linear_elastic, ElementRotation::corotational,
      Integrator::implicit_euler, 0.0, 1);
  fem("corotational", "explicit_central_difference", ElementLaw::linear_elastic, ElementRotation::corotational,
      Integrator::explicit_central_difference, 0.0, 1);
  fem("corotational", "quasi_static", ElementLaw::linear_elastic, ElementRotation::corotational,
      Integrator::quasi_static, 0.0, 3);
  fem("stvk", "implicit_euler", ElementLaw::st_venant_kirchhoff, ElementRotation::corotational,
      Integrator::implicit_euler, 0.0, 3);
  fem("stvk_penalty", "implicit_euler", ElementLaw::st_venant_kirchhoff, ElementRotation::corotational,
      Integrator::implicit_euler, 1.0e5, 3);
  fem("stvk_penalty", "explicit_central_difference", ElementLaw::st_venant_kirchhoff, ElementRotation::none,
      Integrator::explicit_central_difference, 1.0e5, 1);
  all.push_back({"mass_spring_volume", "explicit_central_difference", {}, true});
  return all;
}

struct Record {
  std::string model, integrator, scene;
  std::int64_t tets = 0;
  double step_us_median = 0.0, step_us_p99 = 0.0, error_rms_m = 0.0, error_max_m = 0.0, volume_change_pct = 0.0;
  int steps = 0;
  bool healthy = true;
};

double mesh_volume_m3(const nav::TetMesh& mesh, std::span<const double> x) {
  double volume_m3 = 0.0;
  const auto at = [&](std::int32_t n) {
    const std::size_t i = 3 * static_cast<std::size_t>(n);
    return nav::Point3{x[i], x[i + 1], x[i + 2]};
  };
  for (const auto& t : mesh.tets) volume_m3 += nav::signed_tet_volume_m3(at(t[0]), at(t[1]), at(t[2]), at(t[3]));
  return volume_m3;
}

/// Longest a case may run: one whose first steps project beyond it is left out (an explicit
/// step on the 22k liver costs more than an implicit one and needs 20000 of them a second).
constexpr double kCaseBudgetS = 90.0;

/// Runs `steps` steps of `advance` (which gets the ramp fraction) and times each one; empty
/// when the first 20 project a run longer than kCaseBudgetS.
std::vector<double> timed_steps(int steps, const std::function<void(double)>& advance) {
  std::vector<double> step_us;
  for (int s = 0; s < steps; ++s) {
    const double ramp = std::min(1.0, 2.0 * (s + 1) / steps);
    const auto start = std::chrono::steady_clock::now();
    advance(ramp);
    step_us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    if (s == 19) {
      double first_us = 0.0;
      for (double us : step_us) first_us += us;
      if (first_us / 20.0 * steps > 1e6 * kCaseBudgetS) return {};
    }
  }
  std::sort(step_us.begin(), step_us.end());
  return step_us;
}

/// The scene's loads and imposed displacement times `fraction` (a quasi-static step from rest
/// under the full load would diverge).
nav::TissueInputs ramped(const nav::TissueInputs& full, double fraction) {
  nav::TissueInputs inputs = full;
  inputs.load_scale = fraction;
  for (int c = 0; c < 3; ++c) inputs.prescribed_displacement_m[c] *= fraction;
  return inputs;
}

/// The case's record, or nothing when it is over the time budget.
std::optional<Record> run_case(const Case& c, const nav::TetMesh& mesh, const nav::LiverScene& scene,
                               std::span<const double> reference) {
  Record record{c.model, c.integrator, scene.name, static_cast<std::int64_t>(mesh.tets.size())};
  std::vector<double> step_us, x;
  if (c.mass_spring) {
    nav::MassSpringOptions o;
    o.damping_per_s = kDampingPerS;
    o.step_s = 0.8 * nav::make_mass_spring_model(mesh, scene.scene, o).value().stable_step_s();
    const nav::MassSpringModel model = nav::make_mass_spring_model(mesh, scene.scene, o).value();
    auto data = nav::make_mass_spring_data(model).value();
    record.steps = static_cast<int>(std::ceil(kSettleS / o.step_s));
    step_us = timed_steps(record.steps, [&](double f) { nav::step(model, data, ramped(scene.inputs, f)); });
    x.assign(data.positions_m.begin(), data.positions_m.end());
    record.healthy = data.health.healthy();
  } else {
    nav::TissueSolverOptions o = c.options;
    if (o.integrator == Integrator::explicit_central_difference)
      o.step_s = 0.8 * nav::make_tet_fem_model(mesh, scene.scene, o).value().stable_step_s();
    const nav::TetFemModel model = nav::make_tet_fem_model(mesh, scene.scene, o).value();
    auto data = nav::make_tet_fem_data(model).value();
    record.steps = static_cast<int>(std::ceil(kSettleS / o.step_s));
    step_us = timed_steps(record.steps, [&](double f) { nav::step(model, data, ramped(scene.inputs, f)); });
    x.assign(data.positions_m.begin(), data.positions_m.end());
    record.healthy =
        !data.health.has(nav::HealthFlag::non_finite_state) && !data.health.has(nav::HealthFlag::inverted_element);
  }
  if (step_us.empty()) return std::nullopt;
  record.step_us_median = step_us[step_us.size() / 2];
  record.step_us_p99 = step_us[std::min(step_us.size() - 1, step_us.size() * 99 / 100)];
  double sum_m2 = 0.0;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    double d2 = 0.0;
    for (int i = 0; i < 3; ++i) d2 += (x[3 * n + i] - reference[3 * n + i]) * (x[3 * n + i] - reference[3 * n + i]);
    sum_m2 += d2;
    record.error_max_m = std::max(record.error_max_m, std::sqrt(d2));
  }
  record.error_rms_m = std::sqrt(sum_m2 / static_cast<double>(mesh.nodes_m.size()));
  const double rest_m3 = nav::total_volume_m3(mesh);
  record.volume_change_pct = 100.0 * (mesh_volume_m3(mesh, x) - rest_m3) / rest_m3;
  return record;
}

bool write_json(const std::string& path, const std::vector<Record>& records) {
  std::vector<navbench::Json> json;
  for (const Record& r : records)
    json.push_back({{"model", r.model},
                    {"tetrahedra", r.tets},
                    {"integrator", r.integrator},
                    {"scene", r.scene},
                    {"step_us_median", r.step_us_median},
                    {"step_us_p99", r.step_us_p99},
                    {"error_rms_m", r.error_rms_m},
                    {"error_max_m", r.error_max_m},
                    {"volume_change_pct", r.volume_change_pct},
                    {"steps", r.steps},
                    {"healthy", r.healthy}});
  return navbench::write_json_records(path, json);
}

/// Log-log scatter of error_rms_m against step_us_median, one colour per model, circles for
/// the gravity scene and squares for the probe.
void write_svg(const std::string& path, const std::vector<Record>& records) {
  std::FILE* file = navbench::open_bench_output(path);
  if (!file) return;
  const double width = 900, height = 600, left = 80, bottom = 60, right = 260, top = 30;
  const double x_lo = 0.0, x_hi = 6.0, y_lo = -8.0, y_hi = -1.0;  // log10 of us and m
  const auto px = [&](double us) {
    return left + (std::log10(std::max(us, 1.0)) - x_lo) / (x_hi - x_lo) * (width - left - right);
  };
  const auto py = [&](double m) {
    return top + (y_hi - std::log10(std::max(m, 1e-8))) / (y_hi - y_lo) * (height - top - bottom);
  };
  const std::vector<std::string> models{"linear", "corotational", "stvk", "stvk_penalty", "mass_spring_volume"};
  const char* colours[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"};
  std::fprintf(file,
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" "
               "font-size=\"12\">\n",
               width, height);
  std::fprintf(file, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
  for (int d = 0; d <= 6; ++d)
    std::fprintf(file,
                 "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
                 "text-anchor=\"middle\">1e%d us</text>\n",
                 px(std::pow(10.0, d)), top, px(std::pow(10.0, d)), height - bottom, px(std::pow(10.0, d)),
                 height - bottom + 18, d);
  for (int d = -8; d <= -1; ++d)
    std::fprintf(file,
                 "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
                 "text-anchor=\"end\">1e%d m</text>\n",
                 left, py(std::pow(10.0, d)), width - right, py(std::pow(10.0, d)), left - 6, py(std::pow(10.0, d)) + 4,
                 d);
  std::fprintf(file, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">median step time (log)</text>\n",
               (left + width - right) / 2, height - 20);
  std::fprintf(file,
               "<text x=\"16\" y=\"%.1f\" transform=\"rotate(-90 16 %.1f)\" text-anchor=\"middle\">RMS error vs "
               "neo-Hookean (log)</text>\n",
               (top + height - bottom) / 2, (top + height - bottom) / 2);
  for (const Record& r : records) {
    const std::size_t m = static_cast<std::size_t>(std::find(models.begin(), models.end(), r.model) - models.begin());
    const char* colour = colours[std::min<std::size_t>(m, 4)];
    const double cx = px(r.step_us_median), cy = py(r.error_rms_m);
    if (r.scene == "gravity")
      std::fprintf(file,
                   "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"%s\"><title>%s %s %lld tets</title></circle>\n", cx,
                   cy, colour, r.model.c_str(), r.integrator.c_str(), static_cast<long long>(r.tets));
    else
      std::fprintf(
          file,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"9\" height=\"9\" fill=\"%s\"><title>%s %s %lld tets</title></rect>\n",
          cx - 4.5, cy - 4.5, colour, r.model.c_str(), r.integrator.c_str(), static_cast<long long>(r.tets));
  }
  for (std::size_t m = 0; m < models.size(); ++m)
    std::fprintf(file, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"%s\"/><text x=\"%.1f\" y=\"%.1f\">%s</text>\n",
                 width - right + 20, top + 20 + 20.0 * static_cast<double>(m), colours[m], width - right + 32,
                 top + 24 + 20.0 * static_cast<double>(m), models[m].c_str());
  std::fprintf(file, "<text x=\"%.1f\" y=\"%.1f\">circle: gravity, square: probe 2 cm</text>\n</svg>\n",
               width - right + 20, top + 24 + 20.0 * static_cast<double>(models.size()));
  std::fclose(file);
}

}  // namespace

/// Entry point of "navbench full --json FILE [--quick]".
namespace navbench {

int run_full_bench(const std::vector<std::string>& args) {
  const auto parsed = parse_bench_args(args, "usage: navbench full --json FILE [--quick]\n");
  if (!parsed) return 2;
  const std::string& json_path = parsed->json_path;
  const bool quick = parsed->quick;
  std::vector<Record> records;
  const std::vector<int> sizes = quick ? std::vector<int>{1000} : std::vector<int>{1000, 5000, 22019};
  for (int size : sizes) {
    const auto mesh_or_error = nav::load_liver_mesh(NAV_SHARED_LIVER_DIR, size);
    if (!mesh_or_error.ok()) {
      std::fprintf(stderr, "liver mesh of %d tets: %s\n", size, mesh_or_error.error().describe().c_str());
      return 1;
    }
    const nav::TetMesh& mesh = mesh_or_error.value();
    for (const nav::LiverScene& scene : nav::liver_scenes(mesh)) {
      const auto start = std::chrono::steady_clock::now();
      nav::NewtonStaticOptions reference_options;
      reference_options.load_increments = 10;
      const auto reference = nav::solve_newton_static(mesh, scene.scene, scene.inputs, {}, reference_options);
      if (!reference.ok()) {
        std::fprintf(stderr, "reference %s on %zu tets: %s\n", scene.name.c_str(), mesh.tets.size(),
                     reference.error().describe().c_str());
        return 1;
      }
      const double reference_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "%zu tets, %s: neo-Hookean reference in %.1f s (%d Newton iterations)\n", mesh.tets.size(),
                   scene.name.c_str(), reference_s, reference.value().newton_iterations);
      for (const Case& c : cases()) {
        if (quick && c.integrator == "explicit_central_difference" && !c.mass_spring) continue;
        const auto record = run_case(c, mesh, scene, reference.value().positions_m);
        if (!record) {
          std::fprintf(stderr, "  %-18s %-28s left out: over the %.0f s budget of a case\n", c.model.c_str(),
                       c.integrator.c_str(), kCaseBudgetS);
          continue;
        }
        records.push_back(*record);
        const Record& r = records.back();
        std::fprintf(stderr, "  %-18s %-28s %7.0f us (p99 %7.0f)  rms %.2e m  max %.2e m  dV %+.3f %%%s\n",
                     r.model.c_str(), r.integrator.c_str(), r.step_us_median, r.step_us_p99, r.error_rms_m,
                     r.error_max_m, r.volume_change_pct, r.healthy ? "" : "  (flagged)");
      }
    }
  }
  if (!write_json(json_path, records)) return 1;
  const std::size_t dot = json_path.rfind('.');
  write_svg((dot == std::string::npos ? json_path : json_path.substr(0, dot)) + ".svg", records);
  return 0;
}

}  // namespace navbench
