// navtool solve: a static case to equilibrium (nav/tissue/static_equilibrium.hpp), written as a
// .vtu that ParaView opens: the displacement, the out-of-balance force and the reactions per
// node, the Cauchy and von Mises stress per element. Box corners are in the mesh's unit.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/mesh/vtu_writer.hpp"
#include "nav/tissue/elastic_material.hpp"
#include "nav/tissue/node_selection.hpp"
#include "nav/tissue/static_equilibrium.hpp"

namespace navtool {
namespace {

constexpr const char* kUsage =
    "usage: navtool solve --mesh FILE [--unit mm|cm|m] --model linear|corotational|stvk|neo-hookean\n"
    "                     --fix-box X0,Y0,Z0,X1,Y1,Z1 [--gravity GX,GY,GZ] [--force-nodes I,J,... --force-n FX,FY,FZ]\n"
    "                     [--youngs-modulus-pa E] [--poisson-ratio NU] [--density-kg-m3 RHO] [--tolerance T]\n"
    "                     --out FILE.vtu\n";

/// The comma-separated numbers of option `name`, exactly `count` of them (any count when 0).
nav::Result<std::vector<double>> numbers(const CalibOptions& options, const std::string& name, std::size_t count) {
  std::vector<double> values;
  std::stringstream text(options.get(name));
  for (std::string item; std::getline(text, item, ',');) {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || !std::isfinite(value))
      return nav::Error{.message = "'" + item + "' is not a finite number", .field = name};
    values.push_back(value);
  }
  if ((count > 0 && values.size() != count) || values.empty())
    return nav::Error{.message = "expects " + (count > 0 ? std::to_string(count) : std::string("one or more")) +
                                 " comma-separated numbers",
                      .field = name};
  return values;
}

std::optional<nav::StaticLaw> parse_law(const std::string& name) {
  for (nav::StaticLaw law : {nav::StaticLaw::linear, nav::StaticLaw::corotational, nav::StaticLaw::st_venant_kirchhoff,
                             nav::StaticLaw::neo_hookean})
    if (name == nav::static_law_name(law)) return law;
  return std::nullopt;
}

/// The case the options describe: the mesh, its supports, material and loads.
struct StaticCase {
  nav::TetMesh mesh;
  nav::TissueScene scene;
  std::vector<nav::PointForce> point_forces;
  nav::StaticLaw law = nav::StaticLaw::linear;

  nav::TissueInputs loads() const {
    nav::TissueInputs inputs;
    inputs.point_forces = point_forces;
    return inputs;
  }
};

nav::Result<StaticCase> read_case(const CalibOptions& options) {
  const auto unit = nav::parse_length_unit(options.get("--unit", "m"));
  if (!unit) return nav::Error{.message = "unknown unit (mm, cm or m)", .field = "--unit"};
  const auto law = parse_law(options.get("--model"));
  if (!law) return nav::Error{.message = "expects linear, corotational, stvk or neo-hookean", .field = "--model"};
  StaticCase c;
  c.law = *law;
  auto mesh = nav::load_tet_mesh(options.get("--mesh"), *unit);
  if (!mesh) return mesh.error();
  c.mesh = std::move(mesh).value();

  const auto box = numbers(options, "--fix-box", 6);
  if (!box) return box.error();
  const double metres = nav::metres_per_unit(*unit);
  const nav::Bounds3 fixed_box{{metres * box.value()[0], metres * box.value()[1], metres * box.value()[2]},
                               {metres * box.value()[3], metres * box.value()[4], metres * box.value()[5]}};
  auto fixed = nav::nodes_in_box(c.mesh, fixed_box, "--fix-box");
  if (!fixed) return fixed.error();
  c.scene.fixed_nodes = std::move(fixed).value();

  if (options.has("--gravity")) {
    const auto gravity = numbers(options, "--gravity", 3);
    if (!gravity) return gravity.error();
    c.scene.gravity_m_s2 = {gravity.value()[0], gravity.value()[1], gravity.value()[2]};
  }
  const std::pair<const char*, double*> material[] = {
      {"--youngs-modulus-pa", &c.scene.default_material.youngs_modulus_pa},
      {"--poisson-ratio", &c.scene.default_material.poisson_ratio},
      {"--density-kg-m3", &c.scene.default_material.density_kg_m3}};
  for (const auto& [name, value] : material) {
    if (!options.has(name)) continue;
    const auto parsed = numbers(options, name, 1);
    if (!parsed) return parsed.error();
    *value = parsed.value()[0];
  }
  if (nav::Status valid = nav::check_material(c.scene.default_material, "material"); !valid) return valid.error();

  if (options.has("--force-nodes") != options.has("--force-n"))
    return nav::Error{.message = "--force-nodes and --force-n go together", .field = "--force-n"};
  if (options.has("--force-nodes")) {
    const auto nodes = numbers(options, "--force-nodes", 0);
    if (!nodes) return nodes.error();
    const auto force = numbers(options, "--force-n", 3);
    if (!force) return force.error();
    for (double node : nodes.value()) {
      if (node != std::floor(node) || node < 0.0 || node >= static_cast<double>(c.mesh.nodes_m.size()))
        return nav::Error{.message = "node " + std::to_string(node) + " is not a node of the mesh",
                          .field = "--force-nodes"};
      c.point_forces.push_back(
          {static_cast<std::int32_t>(node), {force.value()[0], force.value()[1], force.value()[2]}});
    }
    c.scene.max_point_forces = c.point_forces.size();
  }
  return c;
}

/// Largest Euclidean norm over the 3-vectors of `values`.
double largest_norm(const std::vector<double>& values) {
  double largest = 0.0;
  for (std::size_t i = 0; i + 2 < values.size(); i += 3)
    largest = std::max(largest, std::hypot(values[i], values[i + 1], values[i + 2]));
  return largest;
}

}  // namespace

int solve(const std::vector<std::string>& args) {
  const auto options =
      CalibOptions::parse(args, {"--mesh", "--unit", "--model", "--fix-box", "--gravity", "--force-nodes", "--force-n",
                                 "--youngs-modulus-pa", "--poisson-ratio", "--density-kg-m3", "--tolerance", "--out"});
  if (!options || !options->has("--mesh") || !options->has("--model") || !options->has("--fix-box") ||
      !options->has("--out")) {
    std::fputs(kUsage, stderr);
    return exit_bad_input;
  }
  auto c = read_case(*options);
  if (!c) return report_error(c.error());
  nav::StaticSolveOptions solve_options;
  if (options->has("--tolerance")) {
    const auto tolerance = numbers(*options, "--tolerance", 1);
    if (!tolerance) return report_error(tolerance.error());
    solve_options.relative_tolerance = tolerance.value()[0];
  }
  const auto start = std::chrono::steady_clock::now();
  const auto solved =
      nav::solve_static(c.value().mesh, c.value().scene, c.value().loads(), c.value().law, solve_options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!solved) {
    std::fprintf(stderr, "navtool solve: %s\n", solved.error().describe().c_str());
    return exit_failure;
  }
  const nav::StaticEquilibrium& answer = solved.value();
  const nav::Status written = nav::write_vtu(
      options->get("--out"), c.value().mesh,
      {{"displacement_m", 3, answer.displacement_m},
       {"out_of_balance_force_n", 3, answer.out_of_balance_n},
       {"reaction_force_n", 3, answer.reaction_n}},
      {{"cauchy_stress_pa", 6, answer.cauchy_stress_pa}, {"von_mises_stress_pa", 1, answer.von_mises_stress_pa}});
  if (!written) return report_error(written.error());
  double largest_stress_pa = 0.0;
  for (double s : answer.von_mises_stress_pa) largest_stress_pa = std::max(largest_stress_pa, s);
  std::printf(
      "navtool solve: %s, %zu nodes (%zu fixed), %zu elements: equilibrium after %d iterations in %.2f s, relative "
      "out-of-balance force %.2e (largest %.3g N); largest displacement %.3f mm, von Mises stress %.4g Pa -> %s\n",
      nav::static_law_name(c.value().law), c.value().mesh.nodes_m.size(), c.value().scene.fixed_nodes.size(),
      c.value().mesh.tets.size(), answer.iterations, seconds, answer.relative_out_of_balance,
      largest_norm(answer.out_of_balance_n), 1e3 * largest_norm(answer.displacement_m), largest_stress_pa,
      options->get("--out").c_str());
  return exit_ok;
}

}  // namespace navtool
