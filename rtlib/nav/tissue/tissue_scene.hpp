#pragma once
// What a tissue model is built from (its supports, load regions and solver settings) and
// what it is driven by at every step. Plain data, no Eigen: widely included.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/elastic_material.hpp"

namespace nav {

/// Standard gravity along -z, m/s^2: what a TissueScene that states no gravity gets (state
/// {0, 0, 0} for none, or the patient's own direction).
inline constexpr Point3 kGravityAlongMinusZ_m_s2{0.0, 0.0, -9.81};

/// Supports, load regions and materials of one organ: fixed at init, never changed after.
/// Node lists left empty switch the feature off. Unstated, the material is kLiverParenchyma
/// and gravity kGravityAlongMinusZ_m_s2 (both named here so that a caller sees them).
struct TissueScene {
  ElasticMaterial default_material = kLiverParenchyma;
  /// Material per TetMesh::tet_regions value (elements of unlisted regions use the default).
  std::vector<std::pair<std::int32_t, ElasticMaterial>> region_materials;
  /// When positive, every node gets an equal share of this mass instead of its lumped
  /// density-times-volume share (SOFA's UniformMass).
  double uniform_total_mass_kg = 0.0;
  Point3 gravity_m_s2 = kGravityAlongMinusZ_m_s2;
  /// Nodes held at their rest position.
  std::vector<std::int32_t> fixed_nodes;
  /// Nodes moved by TissueInputs::prescribed_displacement_m (a diaphragm region).
  std::vector<std::int32_t> prescribed_nodes;
  /// Nodes tied by springs to their rest positions carried by a moving frame (hilum,
  /// ligaments), of stiffness spring_stiffness_n_m each.
  std::vector<std::int32_t> spring_nodes;
  double spring_stiffness_n_m = 0.0;
  /// Surface triangles (mesh node indices) loaded by TissueInputs::traction_pa.
  std::vector<std::array<std::int32_t, 3>> traction_triangles;
  /// Penalty stiffness of the spherical probe against the boundary nodes (0: no probe).
  double probe_stiffness_n_m = 0.0;
  /// Most point forces one step accepts.
  std::size_t max_point_forces = 16;
  /// Share of a point force its node keeps in the full-order models (TetFemModel and the
  /// solves on its tables); the rest goes in equal parts to the nodes that share an element
  /// with it, and the point it acts on moves as the same weighted mean of their displacements
  /// (point_displacements_m()). 1 keeps the force on its node; below 1 a needle's
  /// concentrated force spreads over the elements about its node, which the node alone
  /// carries only by inverting them. The reduced model and solve_linear_static take 1 only.
  double point_force_own_share = 1.0;
};

/// The material of element `tet`: its region's in scene.region_materials, else the default.
inline const ElasticMaterial& material_of(const TetMesh& mesh, std::size_t tet, const TissueScene& scene) {
  if (tet < mesh.tet_regions.size())
    for (const auto& [region, material] : scene.region_materials)
      if (region == mesh.tet_regions[tet]) return material;
  return scene.default_material;
}

/// Which rotation the elements are measured in.
enum class ElementRotation {
  corotational,  ///< the polar rotation of each element's deformation gradient
  none,          ///< small displacements: linear elasticity (the linear tensor-mass model)
};

/// The constitutive law of the elements.
enum class ElementLaw {
  linear_elastic,       ///< Hooke's law in each element's frame (see ElementRotation)
  st_venant_kirchhoff,  ///< Green-Lagrange strain (Picinbono's non-linear tensor-mass), with
                        ///< the incompressibility penalty of TissueSolverOptions; rotation
                        ///< invariant by itself, ElementRotation then only warps the solver
};

/// The time integration of a step.
enum class Integrator {
  implicit_euler,               ///< backward Euler, one linearisation per step
  quasi_static,                 ///< one Newton step towards equilibrium per call (Rayleigh
                                ///< damping, if any, resists the step: see TissueSolverOptions)
  explicit_central_difference,  ///< lumped mass, conditionally stable
};

/// How the linear system of an implicit or quasi-static step is solved: conjugate gradients
/// on the system rotated by each element's rotation, at most cg_iterations iterations (fewer
/// only when the residual reaches rounding level), with one of three preconditioners.
enum class LinearSolver {
  ldlt_warped,      ///< LDL^T of the rest system factored at init, warped by node rotations
                    ///< (Courtecuisse et al.); exact in one iteration for linear elements
  cg_jacobi,        ///< the rest system's diagonal
  cg_block_jacobi,  ///< the rest system's 3x3 node blocks, warped by node rotations
};

/// Numerical settings of a tissue model.
struct TissueSolverOptions {
  ElementLaw law = ElementLaw::linear_elastic;
  /// Picinbono's per-element incompressibility gain gamma (st_venant_kirchhoff only): each
  /// element adds the energy V0 gamma |V/V0 - 1|^3 / 3. Zero switches it off.
  double incompressibility_gain_pa = 0.0;
  ElementRotation rotation = ElementRotation::corotational;
  Integrator integrator = Integrator::implicit_euler;
  LinearSolver solver = LinearSolver::ldlt_warped;
  double step_s = 0.01;
  int cg_iterations = 20;  ///< 1 to 3 are typical with ldlt_warped, 20 to 200 with the others
  /// A CG solve that ends above this relative residual raises solver_not_converged.
  double cg_residual_bound = 1e-2;
  /// Rayleigh damping C = a M + b K (b is not available to the explicit integrator). In a
  /// quasi-static step it acts on the step's motion du / h only: a relaxation of the Newton
  /// step that does not move the equilibrium.
  double rayleigh_mass_per_s = 0.0;
  double rayleigh_stiffness_s = 0.0;
};

/// A force on one node, in newtons.
struct PointForce {
  std::int32_t node = 0;
  Point3 force_n{};
};

/// A rigid motion x = R X + t, R from the unit quaternion (w, x, y, z).
struct RigidMotion {
  std::array<double, 4> rotation_wxyz{1.0, 0.0, 0.0, 0.0};
  Point3 translation_m{};
};

/// A rigid sphere pressed against the surface.
struct SphereProbe {
  bool active = false;
  Point3 centre_m{};
  double radius_m = 0.0;
};

/// What drives one step. Every value is checked at the boundary: a step with a non-finite
/// value, an out-of-range node or too many point forces is refused with the state untouched.
struct TissueInputs {
  /// Factor on gravity, point forces and traction, for a load ramp: a quasi-static solve
  /// from rest diverges under the full load at once (its first step is linear), and reaches
  /// it in a few steps of a growing factor. 1 in normal use.
  double load_scale = 1.0;
  std::span<const PointForce> point_forces;
  /// Traction on TissueScene::traction_triangles, per unit rest area.
  Point3 traction_pa{};
  /// Motion of the spring anchors from their rest positions.
  RigidMotion spring_frame;
  /// Displacement of the prescribed nodes from their rest positions, at the end of the step.
  Point3 prescribed_displacement_m{};
  SphereProbe probe;
};

/// What the last step did.
struct TissueStepReport {
  double solver_relative_residual = 0.0;  ///< |b - A x| / |b| of the last linear solve
  int solver_iterations = 0;
  int inverted_elements = 0;
  int probe_contacts = 0;
  double probe_force_n = 0.0;  ///< magnitude of the probe's total force on the tissue
};

}  // namespace nav
