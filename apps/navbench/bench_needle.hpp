#pragma once
// navbench needle: step times of the flexible needle alone, with up to 32 constraint points,
// coupled to the reduced liver (r = 16, up to 32 constraint points) and to the full-order
// corotational liver (about 5k tetrahedra), plus the force
// profile of an insertion-retraction cycle, as JSON records and an SVG plot. The scenes are
// inline here so that the Google Benchmark program (tests/benchmarks/bench_needle.cpp)
// measures the same ones.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "nav/mesh/validation.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/needle/needle_step.hpp"
#include "nav/needle/needle_tissue_model.hpp"
#include "nav/needle/reduced_coupling.hpp"
#include "nav/needle/tissue_surface.hpp"
#include "nav/reduced/reduction.hpp"

namespace navbench {

/// navbench needle --json FILE [--quick]; returns the exit code.
int run_needle_bench(const std::vector<std::string>& args);

namespace needle_scenes {

/// The default 18 G steel needle, 15 cm, in `elements` Timoshenko elements, 1 kHz.
inline nav::NeedleParameters needle(int elements) {
  nav::NeedleParameters p;
  p.element_count = elements;
  return p;
}

/// A capsule (f_p 1 N) over parenchyma, facing the needle (along +x) 5 mm ahead of its tip,
/// and path points every `spacing_m` (up to 32).
inline nav::NeedleTissueScene capsule_and_parenchyma(double spacing_m) {
  nav::NeedleTissueScene scene;
  nav::TissueLayer capsule;
  capsule.surface_point_m = {0.155, 0.0, 0.0};
  capsule.outward_normal = {-1.0, 0.0, 0.0};
  capsule.puncture_force_n = 1.0;
  capsule.cutting_force_n = 0.3;
  capsule.friction_per_length_n_m = 15.0;
  nav::TissueLayer parenchyma = capsule;
  parenchyma.surface_point_m = {0.157, 0.0, 0.0};
  parenchyma.puncture_force_n = 0.2;
  parenchyma.cutting_force_n = 0.2;
  scene.layers = {capsule, parenchyma};
  scene.path_spacing_m = spacing_m;
  scene.max_path_points = 32;
  return scene;
}

/// Drives the base along +x to `x_m` at 20 mm/s (20 um per 1 ms tick).
inline void drive_base_to(const nav::NeedleTissueModel& model, nav::NeedleTissueData& data, double x_m) {
  nav::NeedleTissueInputs inputs;
  double x = data.needle.positions_m[0];
  while (x < x_m - 1e-12 || x > x_m + 1e-12) {
    x += std::max(-2e-5, std::min(2e-5, x_m - x));
    inputs.needle.base.position_m = {x, 0.0, 0.0};
    step(model, data, inputs);
  }
}

/// The embedded liver (about 5k tetrahedra) held at its attachments, no gravity.
struct EmbeddedLiverScene {
  nav::EmbeddedLiver liver = nav::make_embedded_liver(nav::kEmbeddedLiverElementSizeM);
  nav::TissueScene scene() const {
    nav::TissueScene scene;
    scene.default_material = {5000.0, 0.45, 1060.0};
    scene.gravity_m_s2 = {0.0, 0.0, 0.0};
    scene.fixed_nodes = liver.attachment_nodes;
    scene.max_point_forces = 64;
    return scene;
  }
};

/// The same liver reduced: its r = 16 lowest vibration modes, corotational cubature on
/// m = 64 evenly spaced tetrahedra of equal weight (the cost does not depend on which ones
/// ECSW picks), quasi-static with one Newton iteration on the frozen, prefactored tangent.
inline nav::ReducedModel reduced_liver(const EmbeddedLiverScene& liver) {
  nav::ReductionOptions options;
  options.source = nav::ReducedBasisSource::linear_modes;
  options.basis_size = 16;
  const nav::TissueScene scene = liver.scene();
  nav::ReducedBasis basis = nav::make_modal_basis(liver.liver.mesh, scene, nav::TissueSolverOptions{}, options).value();
  const std::size_t tets = liver.liver.mesh.tets.size(), samples = 64;
  for (std::size_t s = 0; s < samples; ++s) {
    basis.sample_tets.push_back(static_cast<std::int32_t>(s * tets / samples));
    basis.sample_weights.push_back(static_cast<double>(tets) / static_cast<double>(samples));
  }
  nav::ReducedSolverOptions reduced;
  reduced.integrator = nav::ReducedIntegrator::quasi_static;
  return nav::make_reduced_model(liver.liver.mesh, scene, nav::TissueSolverOptions{}, basis, reduced).value();
}

/// The needle aimed at the tumour from the nearest boundary node, its tip 5 mm off it.
struct Approach {
  Eigen::Vector3d entry_m, direction;
  nav::NeedlePose base_at(double advanced_m) const {
    const Eigen::Vector3d base = entry_m - (0.155 - advanced_m) * direction;
    const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), direction);
    return {{base.x(), base.y(), base.z()}, {q.w(), q.x(), q.y(), q.z()}};
  }
  /// The base at tick k of the timed motion around `advanced_m`: back and forth along the
  /// shaft by +-0.2 mm in 20 um steps, and sideways by 1 mm sin(k / 100).
  nav::NeedlePose wobbled_base(double advanced_m, int tick) const {
    const int phase = tick % 40;
    nav::NeedlePose pose = base_at(advanced_m + 2e-5 * (phase < 20 ? phase - 10 : 30 - phase));
    const Eigen::Vector3d shifted =
        Eigen::Vector3d(pose.position_m.data()) + 1e-3 * std::sin(1e-2 * tick) * direction.unitOrthogonal();
    pose.position_m = {shifted.x(), shifted.y(), shifted.z()};
    return pose;
  }
};

inline Approach approach_tumour(const EmbeddedLiverScene& liver) {
  const Eigen::Vector3d tumour(liver.liver.tumour_centre_m[0], liver.liver.tumour_centre_m[1],
                               liver.liver.tumour_centre_m[2]);
  Eigen::Vector3d entry = Eigen::Vector3d::Zero();
  double best_m = -1.0;
  for (std::int32_t node : nav::extract_boundary(liver.liver.mesh).mesh_node_of_vertex) {
    const nav::Point3& p = liver.liver.mesh.nodes_m[static_cast<std::size_t>(node)];
    const Eigen::Vector3d x(p[0], p[1], p[2]);
    if (best_m < 0.0 || (x - tumour).norm() < best_m) {
      best_m = (x - tumour).norm();
      entry = x;
    }
  }
  return {entry, (tumour - entry).normalized()};
}

/// The capsule of the liver at the approach's entry, with forces scaled to the coarse mesh
/// (each constraint loads one node), path points every `spacing_m`.
inline nav::NeedleTissueScene liver_capsule(const Approach& approach, double spacing_m) {
  nav::NeedleTissueScene scene = capsule_and_parenchyma(spacing_m);
  scene.layers.resize(1);
  nav::TissueLayer& capsule = scene.layers[0];
  capsule.surface_point_m = {approach.entry_m.x(), approach.entry_m.y(), approach.entry_m.z()};
  capsule.outward_normal = {-approach.direction.x(), -approach.direction.y(), -approach.direction.z()};
  capsule.puncture_force_n = 0.3;
  capsule.cutting_force_n = 0.1;
  capsule.friction_per_length_n_m = 3.0;
  return scene;
}

/// The same scene with its capsule taken from the mesh (its boundary, moving with the liver)
/// instead of the tangent plane at the entry and, with `tumour`, the tumour's surface (the
/// boundary of its elements) as a second layer.
inline nav::NeedleTissueScene liver_surfaces(const EmbeddedLiverScene& liver, const Approach& approach,
                                             double spacing_m, bool tumour) {
  nav::NeedleTissueScene scene = liver_capsule(approach, spacing_m);
  scene.surfaces.push_back(nav::mesh_boundary_surface(liver.liver.mesh));
  scene.layers[0].surface = 0;
  if (tumour) {
    nav::TissueLayer inclusion = scene.layers[0];
    inclusion.surface = 1;
    inclusion.puncture_force_n = 1.0;
    scene.layers.push_back(inclusion);
    scene.surfaces.push_back(
        nav::region_boundary_surface(liver.liver.mesh, static_cast<std::int32_t>(nav::TissueRegion::tumour)).value());
  }
  return scene;
}

/// Path spacing of the reduced-liver cases: 32 points within 5 cm of the entry.
inline constexpr double kReducedPathSpacingM = 0.0015;

/// Inserts at 20 um per tick until `points` path points hold the shaft (at most 10 cm);
/// returns how far the base advanced.
template <class Model, class Data>
double insert_until(const Model& model, Data& data, const Approach& approach, int points) {
  double advanced_m = 0.0;
  nav::NeedleInputs inputs;
  while (data.interaction.report.active_path_points < points && advanced_m < 0.1) {
    inputs.base = approach.base_at(advanced_m += 2e-5);
    step(model, data, inputs);
  }
  return advanced_m;
}

}  // namespace needle_scenes
}  // namespace navbench
