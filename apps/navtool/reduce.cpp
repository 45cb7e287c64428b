// navtool reduce: the offline reduction of a liver. Builds the reduction scene of the mesh
// (liver_reduction_scene: held in the anchor's box, gravity, a diaphragm patch at the top),
// solves the seeded training loads with the full-order corotational model, builds the basis
// (vibration modes, modal derivatives or POD of the snapshots) and its force reduction, prints
// the energy captured per mode and the cubature size, and writes the reduced-basis artifact.
// With --extend LOWER it builds the next rung of an escalation ladder instead: LOWER's columns
// first, completed (extend_basis) by POD directions of a training whose needle forces and
// diaphragm displacements --load-scale widens (the probe pushes are already near what the
// full-order training solve converges on; widened loads it cannot solve are left out and
// named), with a force reduction and envelope trained on it. Either way the basis's error
// estimate is then calibrated on the held-out loads (error_calibration.hpp).
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/reduced/error_calibration.hpp"
#include "nav/reduced/reduced_artifact.hpp"
#include "nav/reduced/reduced_ladder_basis.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/tissue/liver_scenes.hpp"

namespace navtool {
namespace {

constexpr const char* kReduceUsage =
    "usage: navtool reduce (--liver-dir DIR [--tets N] | --mesh FILE [--unit mm|cm|m])\n"
    "                      (--method modes|modal-derivatives|pod | --extend LOWER.navrb) --r R\n"
    "                      --force linear|corotational|stvk|stvk-cubic [--samples M] [--seed S]\n"
    "                      [--load-scale S] --out FILE [--json]\n"
    "  --extend LOWER   the next rung of a ladder: LOWER's columns first (an artifact of this mesh,\n"
    "                   R above its size), then POD directions of the training; method and force\n"
    "                   are LOWER's (--force, if given, must match)\n"
    "  --load-scale S   multiplies the training's needle forces and diaphragm displacements\n"
    "                   (default 1; gravity and probe pushes stay): a wider training for an\n"
    "                   upper rung, e.g. 3; above 1, loads the full order cannot solve are\n"
    "                   left out and named\n"
    "  --threads N      training loads solved at once, and threads sharing the error\n"
    "                   estimate's calibration (default: the machine's cores); the artifact\n"
    "                   does not depend on it\n";

/// The command line of reduce.
struct ReduceArgs {
  std::string liver_dir, mesh_file, out;
  std::string extend;       ///< the lower rung's artifact, or empty
  double load_scale = 1.0;  ///< of the training's needle forces and diaphragm displacements
  int threads = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  int tets = 22019;
  nav::LengthUnit unit = nav::LengthUnit::metre;
  nav::ReductionOptions reduction;
  std::string method, force;
  std::uint64_t seed = 1;
  bool json = false;
};

/// A command-line name and its value.
template <typename T>
struct Named {
  const char* name;
  T value;
};

constexpr Named<nav::ReducedBasisSource> kMethods[] = {
    {"modes", nav::ReducedBasisSource::linear_modes},
    {"modal-derivatives", nav::ReducedBasisSource::modal_derivatives},
    {"pod", nav::ReducedBasisSource::pod}};
constexpr Named<nav::ReducedForceKind> kForces[] = {{"linear", nav::ReducedForceKind::linear},
                                                    {"corotational", nav::ReducedForceKind::corotational_cubature},
                                                    {"stvk", nav::ReducedForceKind::stvk_cubature},
                                                    {"stvk-cubic", nav::ReducedForceKind::stvk_cubic_polynomial}};

template <typename T, std::size_t N>
const Named<T>* find_name(const Named<T> (&table)[N], const std::string& name) {
  for (const Named<T>& entry : table)
    if (name == entry.name) return &entry;
  return nullptr;
}

template <typename T, std::size_t N>
std::string name_of(const Named<T> (&table)[N], T value) {
  for (const Named<T>& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}

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
    } else if (a == "--extend") {
      parsed.extend = args[++i];
    } else if (a == "--load-scale") {
      if (!parse_number(args[++i], parsed.load_scale) || !(parsed.load_scale > 0.0 && parsed.load_scale <= 100.0))
        return fail("--load-scale wants a factor in (0, 100], not '" + args[i] + "'");
    } else if (a == "--threads") {
      if (!parse_number(args[++i], parsed.threads) || parsed.threads < 1 || parsed.threads > 256)
        return fail("--threads wants a count from 1 to 256, not '" + args[i] + "'");
    } else if (a == "--unit") {
      const auto unit = nav::parse_length_unit(args[++i]);
      if (!unit) return fail("unknown unit '" + args[i] + "' (mm, cm or m)");
      parsed.unit = *unit;
    } else if (a == "--tets") {
      if (!parse_number(args[++i], parsed.tets) || parsed.tets < 100)
        return fail("--tets wants a count of at least 100");
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
      const auto* method = find_name(kMethods, parsed.method);
      if (method == nullptr) return fail("unknown --method '" + parsed.method + "' (modes, modal-derivatives or pod)");
      parsed.reduction.source = method->value;
    } else if (a == "--force") {
      parsed.force = args[++i];
      const auto* force = find_name(kForces, parsed.force);
      if (force == nullptr)
        return fail("unknown --force '" + parsed.force + "' (linear, corotational, stvk or stvk-cubic)");
      parsed.reduction.force_kind = force->value;
    } else {
      return fail("unexpected argument '" + a + "'");
    }
  }
  if (parsed.liver_dir.empty() == parsed.mesh_file.empty()) return fail("give either --liver-dir or --mesh");
  if (!parsed.extend.empty() && !parsed.method.empty())
    return fail("--extend takes its method from the lower artifact: drop --method");
  if (parsed.extend.empty() && (parsed.method.empty() || parsed.force.empty()))
    return fail("--method and --force are required");
  if (parsed.out.empty()) return fail("--out is required");
  return parsed;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The training snapshots, the loads left out of them and the time they took.
struct Training {
  nav::Snapshots snapshots;
  std::vector<std::string> skipped;  ///< names of loads whose full-order solve failed (widened training only)
  double seconds = 0.0;
};

/// Solves the training loads. A widened training (load_scale above 1) goes beyond what the
/// full order may solve (elements invert under a 2x diaphragm move on liverFine): there a load
/// whose solve fails is left out and named, and only none solved at all is an error.
nav::Result<Training> solve_training(const nav::TetMesh& mesh, const nav::TissueScene& scene,
                                     std::span<const nav::TrainingLoad> loads, double load_scale, int threads) {
  const auto start = std::chrono::steady_clock::now();
  nav::StaticSolveOptions options;
  options.threads = threads;
  Training t;
  if (!(load_scale > 1.0)) {
    auto all = nav::solve_static_loads(mesh, scene, loads, options);
    if (!all.ok()) return all.error();
    t.snapshots = std::move(all).value();
  } else {
    const auto each = nav::solve_each_static_load(mesh, scene, loads, options);
    for (std::size_t k = 0; k < loads.size(); ++k) {
      if (!each[k].ok()) {
        t.skipped.push_back(loads[k].name);
        continue;
      }
      nav::append_snapshots(t.snapshots, each[k].value());
    }
    if (t.snapshots.count == 0)
      return nav::Error{.message = "no training load converged at --load-scale " + std::to_string(load_scale)};
  }
  t.seconds = seconds_since(start);
  return t;
}

/// Calibrates the error estimate of `basis` on the held-out loads the full order solves (the
/// others, beyond what it solves at a widened scale, are left out).
nav::Result<nav::ErrorCalibrationReport> calibrate(const nav::TetMesh& mesh, const nav::TissueScene& scene,
                                                   const nav::TrainingLoadOptions& options, int threads,
                                                   nav::ReducedBasis& basis) {
  const auto held_out = nav::make_training_loads(mesh, scene, options, nav::LoadSet::held_out);
  nav::StaticSolveOptions solve;
  solve.threads = threads;
  solve.snapshot_fractions = {1.0};
  const auto solved = nav::solve_each_static_load(mesh, scene, held_out, solve);
  std::vector<nav::TrainingLoad> loads;
  std::vector<std::vector<double>> full_order;
  for (std::size_t k = 0; k < held_out.size(); ++k) {
    if (!solved[k].ok()) continue;
    loads.push_back(held_out[k]);
    full_order.push_back(solved[k].value().displacements_m);
  }
  nav::ErrorCalibrationOptions calibration;
  calibration.threads = threads;
  return nav::calibrate_error_estimate(mesh, scene, loads, full_order, basis, calibration);
}

/// The per-mode figure: the cumulative captured energy fraction for POD, the frequency in Hz
/// of a vibration mode, nothing (0) for modal derivatives beyond the modes. Columns from
/// `lower_r` on (an extended basis) are the cumulative fraction of the energy the lower rung
/// missed.
void print_report(const ReduceArgs& args, const nav::TetMesh& mesh, const nav::ReducedBasis& basis, int lower_r,
                  const Training& training, const nav::ErrorCalibrationReport& held_out, double reduction_s) {
  std::string skipped;
  for (const std::string& name : training.skipped) skipped += (skipped.empty() ? "\"" : ", \"") + name + "\"";
  const bool pod = basis.source == nav::ReducedBasisSource::pod;
  const nav::ReducedErrorCalibration& e = basis.error_calibration;
  const auto own = static_cast<std::size_t>(lower_r > 0 ? lower_r : basis.basis_size);
  const auto figure = [&](std::size_t k) {
    const double v = basis.column_values[k];
    return pod || k >= own ? v : std::sqrt(std::max(v, 0.0)) / (2.0 * std::numbers::pi);
  };
  const auto values = [&](std::size_t from, std::size_t to) {
    std::string list;
    for (std::size_t k = from; k < to; ++k) {
      char item[64];
      std::snprintf(item, sizeof(item), "%s%.9g", k == from ? "" : ", ", figure(k));
      list += item;
    }
    return list;
  };
  if (args.json) {
    std::string extension;
    if (lower_r > 0)
      extension = "\"lower\": \"" + args.extend + "\", \"lower_r\": " + std::to_string(lower_r) +
                  ", \"extension_energy_fraction\": [" + values(own, basis.column_values.size()) + "], ";
    std::printf(
        "{\"out\": \"%s\", \"method\": \"%s\", \"force\": \"%s\", \"nodes\": %zu, \"tetrahedra\": %zu, \"r\": %d, %s"
        "\"training_loads\": %d, \"load_scale\": %.6g, \"skipped_loads\": [%s], \"%s\": [%s], \"cubature_samples\": "
        "%zu, "
        "\"training_residual_bound\": %.6g, \"error_estimate\": {\"gain\": %.6g, "
        "\"held_out_loads\": %d, \"correlation\": %.4f, \"lowest_ratio\": %.4f, \"highest_ratio\": %.4f}, "
        "\"training_s\": %.2f, \"reduction_s\": %.2f}\n",
        args.out.c_str(), args.method.c_str(), args.force.c_str(), mesh.nodes_m.size(), mesh.tets.size(),
        basis.basis_size, extension.c_str(), training.snapshots.count, args.load_scale, skipped.c_str(),
        pod ? "captured_energy_fraction" : "mode_frequency_hz", values(0, own).c_str(), basis.sample_tets.size(),
        basis.training_residual_bound, e.gain, e.held_out_loads, e.correlation, e.lowest_ratio, e.highest_ratio,
        training.seconds, reduction_s);
    return;
  }
  std::printf(
      "mesh: %zu nodes, %zu tetrahedra; %d training loads (scale %g) solved in %.1f s on %d threads; reduction in "
      "%.1f s\n",
      mesh.nodes_m.size(), mesh.tets.size(), training.snapshots.count, args.load_scale, training.seconds, args.threads,
      reduction_s);
  if (!skipped.empty())
    std::printf("left out (the full order does not solve them at this scale): %s\n", skipped.c_str());
  if (lower_r > 0)
    std::printf("extends %s: its %d columns first, then %d new\n", args.extend.c_str(), lower_r,
                basis.basis_size - lower_r);
  std::printf("%-6s %s\n", "mode", pod ? "captured energy (cumulative)" : "frequency (Hz; 0: modal derivative)");
  for (std::size_t k = 0; k < basis.column_values.size(); ++k) {
    if (k == own) std::printf("%-6s %s\n", "mode", "captured energy of what the lower rung misses (cumulative)");
    if (pod || k >= own) {
      std::printf("%-6zu %.6f %%\n", k + 1, 100.0 * figure(k));
    } else {
      std::printf("%-6zu %.4f\n", k + 1, figure(k));
    }
  }
  std::printf("cubature: %zu sampled tetrahedra of %zu\n", basis.sample_tets.size(), mesh.tets.size());
  std::printf("training residual bound: %.4g\n", basis.training_residual_bound);
  std::printf(
      "error estimate: %.3g times the displacement the basis misses under the point forces; on %d held-out loads "
      "with point forces: correlation %.3f with the true largest nodal error, true / estimated %.2f to %.2f\n",
      e.gain, e.held_out_loads, e.correlation, e.lowest_ratio, e.highest_ratio);
  for (const nav::HeldOutEstimate& load : held_out.loads)
    std::printf("  held out %-28s true %.3f mm, estimated %.3f mm\n", load.load.c_str(), 1e3 * load.true_error_m,
                1e3 * load.estimated_error_m);
  for (const nav::Error& unsolved : held_out.unsolved)
    std::printf("  left out (the reduced model does not solve it): %s\n", unsolved.describe().c_str());
  std::printf("written: %s\n", args.out.c_str());
}

/// The lower rung of --extend: an artifact of `mesh`, smaller than --r, of the --force asked
/// for (if any). Fills args' method and force from it.
nav::Result<nav::ReducedBasis> load_lower(ReduceArgs& args, const nav::TetMesh& mesh) {
  auto lower = nav::load_reduced_basis(args.extend, &mesh);
  if (!lower.ok()) return nav::Error{.message = "--extend: " + lower.error().describe()};
  const nav::ReducedBasis& b = lower.value();
  if (args.reduction.basis_size <= b.basis_size)
    return nav::Error{.message = "--r " + std::to_string(args.reduction.basis_size) + " must be above the " +
                                 std::to_string(b.basis_size) + " columns of the lower rung " + args.extend};
  const std::string force = name_of(kForces, b.force_kind);
  if (!args.force.empty() && args.force != force)
    return nav::Error{.message = "--force " + args.force + " differs from the lower rung's (" + force + ", " +
                                 args.extend + "): the rungs of a ladder share one element law"};
  args.force = force;
  args.method = name_of(kMethods, b.source);
  args.reduction.force_kind = b.force_kind;
  args.reduction.source = b.source;
  return lower;
}

}  // namespace

int reduce(const std::vector<std::string>& args) {
  auto parsed = parse_args(args);
  if (!parsed) return exit_bad_input;
  const auto mesh_or_error = parsed->liver_dir.empty() ? nav::load_tet_mesh(parsed->mesh_file, parsed->unit)
                                                       : nav::load_liver_mesh(parsed->liver_dir, parsed->tets);
  if (!mesh_or_error.ok()) {
    std::fprintf(stderr, "navtool reduce: %s\n", mesh_or_error.error().describe().c_str());
    return exit_bad_input;
  }
  const nav::TetMesh& mesh = mesh_or_error.value();
  std::optional<nav::ReducedBasis> lower;
  if (!parsed->extend.empty()) {
    auto loaded = load_lower(*parsed, mesh);
    if (!loaded.ok()) {
      std::fprintf(stderr, "navtool reduce: %s\n", loaded.error().describe().c_str());
      return exit_bad_input;
    }
    lower = std::move(loaded).value();
  }
  const nav::TissueScene scene = nav::liver_reduction_scene(mesh);
  nav::TrainingLoadOptions load_options;
  load_options.seed = parsed->seed;
  load_options.needle_force_n *= parsed->load_scale;
  load_options.diaphragm_amplitude_m *= parsed->load_scale;
  const auto loads = nav::make_training_loads(mesh, scene, load_options, nav::LoadSet::training);
  const auto training = solve_training(mesh, scene, loads, parsed->load_scale, parsed->threads);
  if (!training.ok()) {
    std::fprintf(stderr, "navtool reduce: training: %s\n", training.error().describe().c_str());
    return exit_failure;
  }
  const auto start = std::chrono::steady_clock::now();
  const nav::Snapshots& s = training.value().snapshots;
  const nav::TissueSolverOptions solver = nav::reduction_solver_options(parsed->reduction.force_kind);
  auto basis =
      lower ? nav::extend_basis(mesh, scene, solver, *lower, parsed->reduction.basis_size, s.displacements_m, s.count)
      : parsed->reduction.source == nav::ReducedBasisSource::pod
          ? nav::make_pod_basis(mesh, scene, solver, parsed->reduction, s.displacements_m, s.count)
          : nav::make_modal_basis(mesh, scene, solver, parsed->reduction);
  if (!basis.ok()) {
    std::fprintf(stderr, "navtool reduce: basis: %s\n", basis.error().describe().c_str());
    return exit_failure;
  }
  const auto reduced =
      nav::add_force_reduction(mesh, scene, solver, parsed->reduction, s.displacements_m, s.count, basis.value());
  if (!reduced.ok()) {
    std::fprintf(stderr, "navtool reduce: force reduction: %s\n", reduced.error().describe().c_str());
    return exit_failure;
  }
  const auto calibrated = calibrate(mesh, scene, load_options, parsed->threads, basis.value());
  if (!calibrated.ok()) {
    std::fprintf(stderr, "navtool reduce: error estimate: %s\n", calibrated.error().describe().c_str());
    return exit_failure;
  }
  const double reduction_s = seconds_since(start);
  const auto saved = nav::save_reduced_basis(parsed->out, basis.value());
  if (!saved.ok()) {
    std::fprintf(stderr, "navtool reduce: %s\n", saved.error().describe().c_str());
    return exit_failure;
  }
  print_report(*parsed, mesh, basis.value(), lower ? lower->basis_size : 0, training.value(), calibrated.value(),
               reduction_s);
  return exit_ok;
}

}  // namespace navtool
