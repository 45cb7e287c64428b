#include "nav/reduced/training_loads.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <system_error>
#include <thread>
#include <utility>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {
namespace {

Point3 normalized(const Point3& v) {
  const double length = norm(v);
  return length > 0.0 ? (1.0 / length) * v : Point3{0.0, 0.0, 0.0};
}

/// A unit vector uniformly distributed on the sphere.
Point3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  for (;;) {
    const Point3 v{normal(rng), normal(rng), normal(rng)};
    if (norm(v) > 1e-6) return normalized(v);
  }
}

/// `v` rotated by `angle_rad` about the unit `axis` (Rodrigues).
Point3 rotated(const Point3& v, const Point3& axis, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return c * v + s * cross(axis, v) + ((1.0 - c) * dot(axis, v)) * axis;
}

/// A uniform draw in [lo, hi].
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

/// Boundary nodes and their area-weighted outward normals.
struct Surface {
  std::vector<std::int32_t> nodes;
  std::vector<Point3> normals;
};

Surface surface_of(const TetMesh& mesh) {
  const TetMeshBoundary boundary = extract_boundary(mesh);
  Surface surface{boundary.mesh_node_of_vertex, std::vector<Point3>(boundary.mesh_node_of_vertex.size(), Point3{})};
  for (const auto& t : boundary.surface.triangles) {
    const auto& v = boundary.surface.vertices_m;
    const Point3 n = cross(v[static_cast<std::size_t>(t[1])] - v[static_cast<std::size_t>(t[0])],
                           v[static_cast<std::size_t>(t[2])] - v[static_cast<std::size_t>(t[0])]);
    for (const std::int32_t corner : t) {
      Point3& sum = surface.normals[static_cast<std::size_t>(corner)];
      sum = sum + n;
    }
  }
  for (Point3& n : surface.normals) n = normalized(n);
  return surface;
}

/// Seeded order of the candidates: the training set takes them from the front, the held-out
/// set from the back, so the two never share a point.
template <typename T>
std::vector<T> shuffled(std::vector<T> items, std::mt19937_64& rng) {
  for (std::size_t i = items.size(); i > 1; --i) std::swap(items[i - 1], items[static_cast<std::size_t>(rng() % i)]);
  return items;
}

/// The index of the `k`-th pick (training: k, held-out: size-1-k); wraps around on small meshes.
std::size_t pick(std::size_t size, int k, LoadSet set) {
  const std::size_t index = static_cast<std::size_t>(k) % size;
  return set == LoadSet::training ? index : size - 1 - index;
}

/// The `candidates` within `radius_m` of node `centre`, nearest first, at most `count` (the
/// centre alone when none is).
std::vector<std::int32_t> patch_around(const TetMesh& mesh, const std::vector<std::int32_t>& candidates,
                                       std::int32_t centre, double radius_m, std::size_t count) {
  std::vector<std::pair<double, std::int32_t>> near;
  const Point3& c = mesh.nodes_m[static_cast<std::size_t>(centre)];
  for (const std::int32_t n : candidates) {
    const double d = norm(mesh.nodes_m[static_cast<std::size_t>(n)] - c);
    if (d <= radius_m) near.emplace_back(d, n);
  }
  std::sort(near.begin(), near.end());
  std::vector<std::int32_t> patch;
  for (std::size_t k = 0; k < std::min(count, near.size()); ++k) patch.push_back(near[k].second);
  if (patch.empty()) patch.push_back(centre);
  return patch;
}

/// The largest position change of a node between `a` and `b`.
double largest_move_m(std::span<const double> a, std::span<const double> b) {
  double largest_m2 = 0.0;
  for (std::size_t i = 0; i + 2 < a.size(); i += 3) {
    const double dx = a[i] - b[i], dy = a[i + 1] - b[i + 1], dz = a[i + 2] - b[i + 2];
    largest_m2 = std::max(largest_m2, dx * dx + dy * dy + dz * dz);
  }
  return std::sqrt(largest_m2);
}

/// Solves `load` from rest, ramping it over `ramp_steps`, and appends the equilibrium at each
/// of options.snapshot_fractions to `snapshots` (3 n each); counts the steps taken.
Status solve_one(const TetFemModel& model, TetFemData& data, const TrainingLoad& load,
                 const StaticSolveOptions& options, int ramp_steps, int& total_steps, std::vector<double>& snapshots) {
  const std::span<const double> rest = model.rest_positions_m();
  std::copy(rest.begin(), rest.end(), data.positions_m.begin());
  std::fill(data.velocities_m_s.begin(), data.velocities_m_s.end(), 0.0);
  data.health.clear_all();
  std::vector<double> previous(rest.begin(), rest.end());
  double last_move_m = 0.0, reached = 0.0;
  const std::size_t first_snapshot = snapshots.size();
  for (const double target : options.snapshot_fractions) {
    const int stage_ramp = std::max(1, static_cast<int>(std::lround(ramp_steps * (target - reached))));
    bool converged = false;
    for (int s = 1; s <= stage_ramp + options.max_steps && !converged; ++s) {
      const double fraction = reached + (target - reached) * std::min(1.0, static_cast<double>(s) / stage_ramp);
      step(model, data, load.inputs(fraction));
      ++total_steps;
      if (data.health.has(HealthFlag::non_finite_state) || data.health.has(HealthFlag::inverted_element)) {
        snapshots.resize(first_snapshot);
        return Error{.message = "full-order solve failed (non-finite state or inverted elements) at load fraction " +
                                std::to_string(fraction) + " with a ramp over " + std::to_string(ramp_steps) + " steps",
                     .field = load.name};
      }
      last_move_m = largest_move_m(data.positions_m, previous);
      std::copy(data.positions_m.begin(), data.positions_m.end(), previous.begin());
      converged = s >= stage_ramp && last_move_m <= options.converged_step_m;
    }
    if (!converged) {
      snapshots.resize(first_snapshot);
      return Error{.message = "full-order solve did not converge at load fraction " + std::to_string(target) +
                              " (ramp over " + std::to_string(ramp_steps) + " steps; last step moved " +
                              std::to_string(last_move_m) + " m)",
                   .field = load.name};
    }
    for (std::size_t i = 0; i < rest.size(); ++i) snapshots.push_back(data.positions_m[i] - rest[i]);
    reached = target;
  }
  return Done{};
}

/// `load` solved from rest on data of its own; a concentrated load can make the relaxed Newton
/// steps overshoot: it is tried again with a ramp 4 and 16 times longer. Nothing escapes the
/// thread it runs on: an exception is this load's Error.
Result<LoadSnapshots> solve_load(const TetFemModel& model, const TrainingLoad& load,
                                 const StaticSolveOptions& options) noexcept {
  try {
    auto data = make_tet_fem_data(model);
    if (!data.ok()) return data.error();
    LoadSnapshots out;
    Status solved = Done{};
    for (int attempt = 0; attempt < 3; ++attempt) {
      solved = solve_one(model, data.value(), load, options, options.ramp_steps << (2 * attempt), out.steps,
                         out.displacements_m);
      if (solved.ok()) {
        out.count = static_cast<int>(options.snapshot_fractions.size());
        return out;
      }
    }
    return solved.error();
  } catch (const std::exception& e) {
    return Error{.message = std::string("full-order solve failed: ") + e.what(), .field = load.name};
  }
}

}  // namespace

TissueInputs TrainingLoad::inputs(double fraction) const {
  TissueInputs in;
  in.load_scale = fraction;
  in.point_forces = point_forces;
  in.prescribed_displacement_m = fraction * prescribed_displacement_m;
  return in;
}

std::vector<TrainingLoad> make_training_loads(const TetMesh& mesh, const TissueScene& scene,
                                              const TrainingLoadOptions& options, LoadSet set) {
  std::mt19937_64 rng(options.seed);
  const bool held_out = set == LoadSet::held_out;
  std::vector<char> constrained(mesh.nodes_m.size(), 0);
  for (const std::int32_t n : scene.fixed_nodes) constrained[static_cast<std::size_t>(n)] = 1;
  for (const std::int32_t n : scene.prescribed_nodes) constrained[static_cast<std::size_t>(n)] = 1;
  const Surface surface = surface_of(mesh);
  std::vector<char> on_surface(mesh.nodes_m.size(), 0);
  std::vector<std::size_t> free_surface;  // indices into surface.nodes
  for (std::size_t v = 0; v < surface.nodes.size(); ++v) {
    on_surface[static_cast<std::size_t>(surface.nodes[v])] = 1;
    if (!constrained[static_cast<std::size_t>(surface.nodes[v])]) free_surface.push_back(v);
  }
  std::vector<std::int32_t> interior;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    if (!on_surface[n] && !constrained[n]) interior.push_back(static_cast<std::int32_t>(n));
  if (interior.empty())  // a mesh too coarse for interior nodes: needles at free surface nodes
    for (const std::size_t v : free_surface) interior.push_back(surface.nodes[v]);
  free_surface = shuffled(std::move(free_surface), rng);
  interior = shuffled(std::move(interior), rng);

  const Point3 g0 = scene.gravity_m_s2;
  const Point3 down = normalized(g0);
  std::vector<TrainingLoad> loads;
  const auto count = [&](int n) { return held_out ? (n + 1) / 2 : n; };
  const auto named = [](const char* kind, double value) {
    char text[48];
    std::snprintf(text, sizeof(text), "%s %.2f", kind, value);
    return std::string(text);
  };

  // Gravity: scales along the scene's direction (held out: between the training scales), then
  // directions tilted about sampled axes (held out: other axes, a smaller angle).
  if (norm(g0) > 0.0) {
    std::vector<double> scales = options.gravity_scales;
    if (held_out) {
      std::vector<double> between;
      for (std::size_t k = 0; k + 1 < scales.size(); ++k) between.push_back(0.5 * (scales[k] + scales[k + 1]));
      scales = between.empty() ? std::vector<double>{0.75 * scales.front()} : between;
    }
    for (const double s : scales) loads.push_back({named("gravity x", s), s * g0, {}, {}});
    std::vector<Point3> axes;
    for (int k = 0; k < 2 * options.gravity_tilts; ++k) axes.push_back(normalized(cross(down, random_direction(rng))));
    for (int k = 0; k < count(options.gravity_tilts); ++k) {
      const Point3& axis = axes[static_cast<std::size_t>(held_out ? options.gravity_tilts + k : k)];
      const double angle_rad = (held_out ? 0.6 : 1.0) * options.gravity_tilt_rad;
      loads.push_back(
          {named("gravity tilt (rad)", angle_rad) + " #" + std::to_string(k), rotated(g0, axis, angle_rad), {}, {}});
    }
  }
  // Probe pushes: inward along the surface normal, tilted up to 30 degrees.
  const std::size_t patch_size = std::max<std::size_t>(1, scene.max_point_forces);
  std::vector<std::int32_t> free_surface_nodes;
  for (const std::size_t v : free_surface) free_surface_nodes.push_back(surface.nodes[v]);
  for (int k = 0; k < count(options.probe_pushes) && !free_surface.empty(); ++k) {
    const std::size_t v = free_surface[pick(free_surface.size(), k, set)];
    const Point3 axis = normalized(cross(surface.normals[v], random_direction(rng)));
    const Point3 push = normalized(rotated(-1.0 * surface.normals[v], axis, uniform(rng, 0.0, std::numbers::pi / 6.0)));
    const double force_n = (held_out ? uniform(rng, 0.4, 0.9) : 1.0) * options.probe_force_n;
    TrainingLoad load{"push " + std::to_string(k), g0, {}, {}};
    const auto patch =
        patch_around(mesh, free_surface_nodes, surface.nodes[v], options.probe_patch_radius_m, patch_size);
    for (const std::int32_t n : patch)
      load.point_forces.push_back({n, (force_n / static_cast<double>(patch.size())) * push});
    loads.push_back(std::move(load));
  }
  // Needle-like forces: a tip's patch of free nodes around a sampled interior node.
  std::vector<std::int32_t> free_nodes;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    if (!constrained[n]) free_nodes.push_back(static_cast<std::int32_t>(n));
  for (int k = 0; k < count(options.needle_forces) && !interior.empty(); ++k) {
    const std::int32_t node = interior[pick(interior.size(), k, set)];
    const Point3 direction = random_direction(rng);
    const double force_n = (held_out ? uniform(rng, 0.4, 0.9) : 1.0) * options.needle_force_n;
    TrainingLoad load{"needle " + std::to_string(k), g0, {}, {}};
    const auto tip = patch_around(mesh, free_nodes, node, options.needle_radius_m, patch_size);
    for (const std::int32_t n : tip)
      load.point_forces.push_back({n, (force_n / static_cast<double>(tip.size())) * direction});
    loads.push_back(std::move(load));
  }
  // Diaphragm: sampled directions, mostly along gravity (breathing pushes the liver down).
  for (int k = 0; k < count(options.diaphragm_moves) && !scene.prescribed_nodes.empty(); ++k) {
    const Point3 direction = normalized(down + 0.5 * random_direction(rng));
    const double amplitude_m = (held_out ? uniform(rng, 0.4, 0.9) : 1.0) * options.diaphragm_amplitude_m;
    loads.push_back({"diaphragm " + std::to_string(k), g0, {}, amplitude_m * direction});
  }
  return loads;
}

TissueScene with_diaphragm(const TetMesh& mesh, TissueScene base, double radius_m) {
  const std::vector<std::int32_t> surface = extract_boundary(mesh).mesh_node_of_vertex;
  const auto at = [&](std::int32_t n) -> const Point3& { return mesh.nodes_m[static_cast<std::size_t>(n)]; };
  const auto far_from_fixed = [&](std::int32_t n) {
    for (const std::int32_t f : base.fixed_nodes)
      if (norm(at(n) - at(f)) < 2.0 * radius_m) return false;
    return true;
  };
  const Point3 up = normalized(-1.0 * base.gravity_m_s2);
  std::int32_t top = -1;
  for (const std::int32_t n : surface)
    if ((top < 0 || dot(at(n), up) > dot(at(top), up)) && far_from_fixed(n)) top = n;
  base.prescribed_nodes.clear();
  if (top < 0) return base;
  for (const std::int32_t n : surface)
    if (norm(at(n) - at(top)) <= radius_m) base.prescribed_nodes.push_back(n);
  std::sort(base.prescribed_nodes.begin(), base.prescribed_nodes.end());
  return base;
}

TissueSolverOptions StaticSolveOptions::default_solver() {
  TissueSolverOptions o;
  o.law = ElementLaw::linear_elastic;
  o.rotation = ElementRotation::corotational;
  o.integrator = Integrator::quasi_static;
  o.solver = LinearSolver::ldlt_warped;
  o.cg_iterations = 3;
  o.rayleigh_mass_per_s = 10.0;
  return o;
}

TissueScene liver_reduction_scene(const TetMesh& mesh) {
  return with_diaphragm(mesh, liver_scenes(mesh).front().scene, kLiverDiaphragmRadiusM);
}

TissueSolverOptions reduction_solver_options(ReducedForceKind kind) {
  TissueSolverOptions o = StaticSolveOptions::default_solver();
  if (kind == ReducedForceKind::stvk_cubature || kind == ReducedForceKind::stvk_cubic_polynomial)
    o.law = ElementLaw::st_venant_kirchhoff;
  if (kind == ReducedForceKind::linear) o.rotation = ElementRotation::none;
  return o;
}

TissueScene scene_for_load(const TissueScene& scene, const TrainingLoad& load) {
  TissueScene s = scene;
  s.gravity_m_s2 = load.gravity_m_s2;
  return s;
}

std::vector<Result<LoadSnapshots>> solve_each_static_load(const TetMesh& mesh, const TissueScene& scene,
                                                          std::span<const TrainingLoad> loads,
                                                          const StaticSolveOptions& options) {
  std::vector<std::optional<Result<LoadSnapshots>>> solved(loads.size());
  std::vector<std::pair<Point3, TetFemModel>> models;  // one per distinct gravity, in first-use order
  std::vector<std::size_t> model_of_load(loads.size(), 0);
  for (std::size_t k = 0; k < loads.size(); ++k) {
    const auto same_gravity = [&](const auto& m) { return m.first == loads[k].gravity_m_s2; };
    auto cached = std::find_if(models.begin(), models.end(), same_gravity);
    if (cached == models.end()) {
      auto model = make_tet_fem_model(mesh, scene_for_load(scene, loads[k]), options.solver);
      if (!model.ok()) {
        solved[k] = model.error();
        continue;
      }
      models.emplace_back(loads[k].gravity_m_s2, std::move(model.value()));
      cached = models.end() - 1;
    }
    model_of_load[k] = static_cast<std::size_t>(cached - models.begin());
  }
  std::atomic<std::size_t> next_load{0};
  const auto solve_remaining = [&] {
    for (std::size_t k = next_load++; k < loads.size(); k = next_load++)
      if (!solved[k]) solved[k] = solve_load(models[model_of_load[k]].second, loads[k], options);
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < std::min<int>(options.threads, static_cast<int>(loads.size())); ++t) {
    try {
      helpers.emplace_back(solve_remaining);
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the ones running take the remaining loads
    }
  }
  solve_remaining();
  for (std::thread& helper : helpers) helper.join();
  std::vector<Result<LoadSnapshots>> out;
  out.reserve(loads.size());
  for (std::optional<Result<LoadSnapshots>>& one : solved) out.push_back(std::move(*one));
  return out;
}

void append_snapshots(Snapshots& snapshots, const LoadSnapshots& load) {
  snapshots.displacements_m.insert(snapshots.displacements_m.end(), load.displacements_m.begin(),
                                   load.displacements_m.end());
  snapshots.count += load.count;
  snapshots.total_steps += load.steps;
}

Result<Snapshots> solve_static_loads(const TetMesh& mesh, const TissueScene& scene, std::span<const TrainingLoad> loads,
                                     const StaticSolveOptions& options) {
  Snapshots out;
  out.displacements_m.reserve(3 * mesh.nodes_m.size() * loads.size() * options.snapshot_fractions.size());
  for (const Result<LoadSnapshots>& one : solve_each_static_load(mesh, scene, loads, options)) {
    if (!one.ok()) return one.error();
    append_snapshots(out, one.value());
  }
  return out;
}

Result<std::vector<double>> solve_reduced_static(const TetMesh& mesh, const TissueScene& scene,
                                                 const ReducedBasis& basis, const TrainingLoad& load,
                                                 const ReducedStaticOptions& options, ReducedStepReport* last_step) {
  ReducedSolverOptions o;
  o.integrator = ReducedIntegrator::quasi_static;
  o.step_s = StaticSolveOptions::default_solver().step_s;
  o.newton_iterations = options.newton_iterations;
  o.frozen_tangent = false;
  o.rayleigh_mass_per_s = options.relaxation_per_s;
  const auto model =
      make_reduced_model(mesh, scene_for_load(scene, load), reduction_solver_options(basis.force_kind), basis, o);
  if (!model.ok()) return model.error();
  auto data = make_reduced_data(model.value());
  if (!data.ok()) return data.error();
  std::vector<double> u(3 * mesh.nodes_m.size(), 0.0), previous(u.size(), 0.0);
  double last_move_m = 0.0;
  for (int s = 1; s <= options.ramp_steps + options.max_steps; ++s) {
    const double fraction = std::min(1.0, static_cast<double>(s) / std::max(1, options.ramp_steps));
    step(model.value(), data.value(), load.inputs(fraction));
    if (data.value().health.has(HealthFlag::non_finite_state))
      return Error{.message = "reduced solve met a non-finite state at step " + std::to_string(s), .field = load.name};
    reconstruct_all_displacements_m(model.value(), data.value(), u);
    last_move_m = largest_move_m(u, previous);
    previous = u;
    if (fraction < 1.0 || last_move_m > options.converged_step_m) continue;
    if (last_step != nullptr) *last_step = data.value().report;
    return u;
  }
  return Error{
      .message = "reduced solve did not converge (last step moved " + std::to_string(last_move_m * 1e9) + " nm)",
      .field = load.name};
}

DisplacementError displacement_error(std::span<const double> u_m, std::span<const double> reference_m,
                                     std::int32_t target_node) {
  DisplacementError e;
  double sum_m2 = 0.0;
  const std::size_t nodes = reference_m.size() / 3;
  for (std::size_t n = 0; n < nodes; ++n) {
    double d2 = 0.0, r2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = u_m[3 * n + c] - reference_m[3 * n + c];
      d2 += d * d;
      r2 += reference_m[3 * n + c] * reference_m[3 * n + c];
    }
    sum_m2 += d2;
    e.max_m = std::max(e.max_m, std::sqrt(d2));
    e.reference_max_m = std::max(e.reference_max_m, std::sqrt(r2));
    if (static_cast<std::int32_t>(n) == target_node) e.target_m = std::sqrt(d2);
  }
  e.rms_m = nodes > 0 ? std::sqrt(sum_m2 / static_cast<double>(nodes)) : 0.0;
  return e;
}

std::int32_t central_target_node(const TetMesh& mesh) {
  Point3 centroid{};
  double volume_m3 = 0.0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const double v = signed_tet_volume_m3(mesh, t);
    Point3 centre{};
    for (const std::int32_t n : mesh.tets[t]) centre = centre + 0.25 * mesh.nodes_m[static_cast<std::size_t>(n)];
    centroid = centroid + v * centre;
    volume_m3 += v;
  }
  centroid = (1.0 / volume_m3) * centroid;
  std::vector<char> on_surface(mesh.nodes_m.size(), 0);
  for (const std::int32_t n : extract_boundary(mesh).mesh_node_of_vertex) on_surface[static_cast<std::size_t>(n)] = 1;
  std::int32_t best = 0;
  double best_m = -1.0;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    const double d = norm(mesh.nodes_m[n] - centroid);
    if (!on_surface[n] && (best_m < 0.0 || d < best_m)) {
      best = static_cast<std::int32_t>(n);
      best_m = d;
    }
  }
  return best;
}

}  // namespace nav
