#pragma once
// Shared scene of the coupled-needle tests: a tissue block held at its bottom face, the
// needle pointing down at its top face, and the top face as the layer it punctures.
#include <cmath>
#include <numbers>

#include "nav/needle/needle_model.hpp"
#include "nav/needle/needle_tissue_scene.hpp"
#include "nav/tissue/tissue_scene.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav::testing {

/// 20 kPa tissue held at its bottom face (z = 0), no gravity, up to 32 point forces.
inline TissueScene held_at_bottom(const TetMesh& mesh) {
  TissueScene scene;
  scene.default_material = {2.0e4, 0.45, 1000.0};
  scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  scene.max_point_forces = 32;
  return scene;
}

/// Linear elements solved exactly (one LDL^T solve), quasi-static.
inline TissueSolverOptions exact_linear_options() {
  TissueSolverOptions options;
  options.rotation = ElementRotation::none;
  options.integrator = Integrator::quasi_static;
  options.solver = LinearSolver::ldlt_warped;
  options.cg_iterations = 1;
  return options;
}

/// The needle pointing down (-z) over (x, y), its tip 5 mm above `top_m` less `lowered_m`.
inline NeedlePose needle_above(double x_m, double y_m, double top_m, double lowered_m) {
  NeedlePose pose;
  pose.position_m = {x_m, y_m, top_m + 0.155 - lowered_m};
  pose.rotation_wxyz = {std::cos(std::numbers::pi / 4), 0.0, std::sin(std::numbers::pi / 4), 0.0};  // +x -> -z
  return pose;
}

/// The top face at (x, y, top) facing +z: f_p 0.2 N, cutting 0.05 N, friction 2 N/m.
inline NeedleTissueScene top_face_layer(double x_m, double y_m, double top_m, double path_spacing_m) {
  NeedleTissueScene scene;
  TissueLayer layer;
  layer.surface_point_m = {x_m, y_m, top_m};
  layer.outward_normal = {0.0, 0.0, 1.0};
  layer.puncture_force_n = 0.2;
  layer.cutting_force_n = 0.05;
  layer.friction_per_length_n_m = 2.0;
  scene.layers = {layer};
  scene.path_spacing_m = path_spacing_m;
  return scene;
}

}  // namespace nav::testing
