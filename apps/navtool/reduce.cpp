// navtool reduce: the offline reduction of a liver. Builds the reduction scene of the mesh
// (liver_reduction_scene: held in the anchor's box, gravity, a diaphragm patch at the top),
// solves the seeded training loads with the full-order corotational model, builds the basis
// (vibration modes, modal derivatives or POD of the snapshots) and its force reduction, prints
// the energy captured per mode and the cubature size, and writes the reduced-basis artifact.
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/reduced/reduced_artifact.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/tissue/liver_scenes.hpp"

namespace navtool {
namespace {

constexpr const char* kReduceUsage =
    "usage: navtool reduce (--liver-dir DIR [--tets N] | --mesh FILE [--unit mm|cm|m])\n"
    "                      --method modes|modal-derivatives|pod --r R\n"
    "                      --force linear|corotational|stvk|stvk-cubic [--samples M] [--seed S]\n"
    "                      --out FILE [--json]\n";

/// The command line of reduce.
struct ReduceArgs {
  std::string liver_dir, mesh_file, out;
  int tets = 22019;
  nav::LengthUnit unit = nav::LengthUnit::metre;
  nav::ReductionOptions reduction;
  std::string method, force;
  std::uint64_t seed = 1;
  bool json = false;
};

template <typename T>
bool parse_number(const std::string& text, T& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

/// Parses the arguments; nullopt (after a message on stderr) if malformed.
std::optional<ReduceArgs> parse_args(const std::vector<std::string>& args) {
  ReduceArgs parsed;
  const auto fail = [](const std::string& message) {
    std::fprintf(stderr, "navtool reduce: %s\n%s", message.c_str(), kReduceUsage);
    return std::nullopt;
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const bool has_value = i + 1 < args.size();
    if (a == "--json") {
      parsed.json = true;
    } else if (!has_value) {
      return fail("unexpected or incomplete argument '" + a + "'");
    } else if (a == "--liver-dir") {
      parsed.liver_dir = args[++i];
    } else if (a == "--mesh") {
      parsed.mesh_file = args[++i];
    } else if (a == "--out") {
      parsed.out = args[++i];
    } else if (a == "--unit") {
      const auto unit = nav::parse_length_unit(args[++i]);
      if (!unit) return fail("unknown unit '" + args[i] + "' (mm, cm or m)");
      parsed.unit = *unit;
    } else if (a == "--tets") {
      if (!parse_number(args[++i], parsed.tets) || parsed.tets < 100) return fail("--tets wants a count of at least 100");
    } else if (a == "--r") {
      if (!parse_number(args[++i], parsed.reduction.basis_size) || parsed.reduction.basis_size < 1)
        return fail("--r wants a positive basis size, not '" + args[i] + "'");
    } else if (a == "--samples") {
      if (!parse_number(args[++i], parsed.reduction.max_cubature_samples) || parsed.reduction.max_cubature_samples < 1)
        return fail("--samples wants a positive number of cubature tetrahedra, not '" + args[i] + "'");
    } else if (a == "--seed") {
      if (!parse_number(args[++i], parsed.seed)) return fail("--seed wants a non-negative integer");
    } else if (a == "--method") {
      parsed.method = args[++i];
      if (parsed.method == "modes") {
        parsed.reduction.source = nav::ReducedBasisSource::linear_modes;
      } else if (parsed.method == "modal-derivatives") {
        parsed.reduction.source = nav::ReducedBasisSource::modal_derivatives;
      } else if (parsed.method == "pod") {
        parsed.reduction.source = nav::ReducedBasisSource::pod;
      } else {
        return fail("unknown --method '" + parsed.method + "' (modes, modal-derivatives or pod)");
      }
    } else if (a == "--force") {
      parsed.force = args[++i];
      if (parsed.force == "linear") {
        parsed.reduction.force_kind = nav::ReducedForceKind::linear;
      } else if (parsed.force == "corotational") {
        parsed.reduction.force_kind = nav::ReducedForceKind::corotational_cubature;
      } else if (parsed.force == "stvk") {
        parsed.reduction.force_kind = nav::ReducedForceKind::stvk_cubature;
      } else if (parsed.force == "stvk-cubic") {
        parsed.reduction.force_kind = nav::ReducedForceKind::stvk_cubic_polynomial;
      } else {
        return fail("unknown --force '" + parsed.force + "' (linear, corotational, stvk or stvk-cubic)");
      }
    } else {
      return fail("unexpected argument '" + a + "'");
    }
  }
  if (parsed.liver_dir.empty() == parsed.mesh_file.empty()) return fail("give either --liver-dir or --mesh");
  if (parsed.method.empty() || parsed.force.empty()) return fail("--method and --force are required");
  if (parsed.out.empty()) return fail("--out is required");
  return parsed;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The per-mode figure: the cumulative captured energy fraction for POD, the frequency in Hz
/// of a vibration mode, nothing (0) for modal derivatives beyond the modes.
void print_report(const ReduceArgs& args, const nav::TetMesh& mesh, const nav::ReducedBasis& basis, int snapshot_count,
                  double training_s, double reduction_s) {
  const bool pod = basis.source == nav::ReducedBasisSource::pod;
  if (args.json) {
    std::string modes;
    for (std::size_t k = 0; k < basis.column_values.size(); ++k) {
      char item[64];
      const double v = basis.column_values[k];
      std::snprintf(item, sizeof(item), "%s%.9g", k == 0 ? "" : ", ", pod ? v : std::sqrt(std::max(v, 0.0)) / (2.0 * std::numbers::pi));
      modes += item;
    }
    std::printf("{\"out\": \"%s\", \"method\": \"%s\", \"force\": \"%s\", \"nodes\": %zu, \"tetrahedra\": %zu, \"r\": %d, "
                "\"training_loads\": %d, \"%s\": [%s], \"cubature_samples\": %zu, \"training_residual_bound\": %.6g, "
                "\"training_s\": %.2f, \"reduction_s\": %.2f}\n",
                args.out.c_str(), args.method.c_str(), args.force.c_str(), mesh.nodes_m.size(), mesh.tets.size(),
                basis.basis_size, snapshot_count, pod ? "captured_energy_fraction" : "mode_frequency_hz", modes.c_str(),
                basis.sample_tets.size(), basis.training_residual_bound, training_s, reduction_s);
    return;
  }
  std::printf("mesh: %zu nodes, %zu tetrahedra; %d training loads solved in %.1f s; reduction in %.1f s\n",
              mesh.nodes_m.size(), mesh.tets.size(), snapshot_count, training_s, reduction_s);
  std::printf("%-6s %s\n", "mode", pod ? "captured energy (cumulative)" : "frequency (Hz; 0: modal derivative)");
  for (std::size_t k = 0; k < basis.column_values.size(); ++k) {
    const double v = basis.column_values[k];
    if (pod) {
      std::printf("%-6zu %.6f %%\n", k + 1, 100.0 * v);
    } else {
      std::printf("%-6zu %.4f\n", k + 1, std::sqrt(std::max(v, 0.0)) / (2.0 * std::numbers::pi));
    }
  }
  std::printf("cubature: %zu sampled tetrahedra of %zu\n", basis.sample_tets.size(), mesh.tets.size());
  std::printf("training residual bound: %.4g\nwritten: %s\n", basis.training_residual_bound, args.out.c_str());
}

}  // namespace

int reduce(const std::vector<std::string>& args) {
  const auto parsed = parse_args(args);
  if (!parsed) return exit_bad_input;
  const auto mesh_or_error = parsed->liver_dir.empty() ? nav::load_tet_mesh(parsed->mesh_file, parsed->unit)
                                                       : nav::load_liver_mesh(parsed->liver_dir, parsed->tets);
  if (!mesh_or_error.ok()) {
    std::fprintf(stderr, "navtool reduce: %s\n", mesh_or_error.error().describe().c_str());
    return exit_bad_input;
  }
  const nav::TetMesh& mesh = mesh_or_error.value();
  const nav::TissueScene scene = nav::liver_reduction_scene(mesh);
  nav::TrainingLoadOptions load_options;
  load_options.seed = parsed->seed;
  const auto loads = nav::make_training_loads(mesh, scene, load_options, nav::LoadSet::training);
  const auto start = std::chrono::steady_clock::now();
  const auto snapshots = nav::solve_static_loads(mesh, scene, loads);
  if (!snapshots.ok()) {
    std::fprintf(stderr, "navtool reduce: training: %s\n", snapshots.error().describe().c_str());
    return exit_failure;
  }
  const double training_s = seconds_since(start);
  const nav::Snapshots& s = snapshots.value();
  const nav::TissueSolverOptions solver = nav::reduction_solver_options(parsed->reduction.force_kind);
  auto basis = parsed->reduction.source == nav::ReducedBasisSource::pod
                   ? nav::make_pod_basis(mesh, scene, solver, parsed->reduction, s.displacements_m, s.count)
                   : nav::make_modal_basis(mesh, scene, solver, parsed->reduction);
  if (!basis.ok()) {
    std::fprintf(stderr, "navtool reduce: basis: %s\n", basis.error().describe().c_str());
    return exit_failure;
  }
  const auto reduced = nav::add_force_reduction(mesh, scene, solver, parsed->reduction, s.displacements_m, s.count, basis.value());
  if (!reduced.ok()) {
    std::fprintf(stderr, "navtool reduce: force reduction: %s\n", reduced.error().describe().c_str());
    return exit_failure;
  }
  const double reduction_s = seconds_since(start) - training_s;
  const auto saved = nav::save_reduced_basis(parsed->out, basis.value());
  if (!saved.ok()) {
    std::fprintf(stderr, "navtool reduce: %s\n", saved.error().describe().c_str());
    return exit_failure;
  }
  print_report(*parsed, mesh, basis.value(), s.count, training_s, reduction_s);
  return exit_ok;
}

}  // namespace navtool
