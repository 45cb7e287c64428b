#pragma once
// What the needle meets: tissue layers (a capsule, parenchyma, a stiff inclusion) with their
// puncture, cutting and friction parameters, the tissue's compliance seen from a point,
// the path-constraint pool and the Gauss-Seidel settings. Plain data, fixed at init.
#include <array>
#include <cstdint>
#include <vector>

#include "nav/core/kernel_isa.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// A puncturable surface of the tissue: closed triangles over tissue nodes (counter-clockwise
/// seen from outside), so that it moves with the tissue: the mesh's boundary (the liver's
/// capsule) or the boundary of a region (a tumour, a vessel); see tissue_surface.hpp.
struct TissueSurface {
  std::vector<std::array<std::int32_t, 3>> triangles;
};

/// One layer: what is inside a surface, with the forces that the needle meets in it. The
/// surface is one of the scene's TissueSurfaces, or else the plane through surface_point_m
/// with its outward unit normal (world frame, at rest), as the verification scenes use. With
/// a full-order tissue, the outermost layer's surface_point_m is where its compliance is probed.
struct TissueLayer {
  Point3 surface_point_m{};
  Point3 outward_normal{0.0, 0.0, 1.0};
  std::int32_t surface = -1;                  ///< index in NeedleTissueScene::surfaces; -1: the plane
  double puncture_force_n = 1.0;              ///< f_p: the surface gives way at this normal force
  double cutting_force_n = 0.3;               ///< resists the tip advancing into uncut tissue
  double friction_per_length_n_m = 10.0;      ///< shaft stick limit per inserted length
  double surface_friction_coefficient = 0.2;  ///< Coulomb, tip on the surface before puncture
};

/// The needle-tissue interaction scene.
struct NeedleTissueScene {
  std::vector<TissueLayer> layers;      ///< outermost first; a deeper layer's index is larger
  std::vector<TissueSurface> surfaces;  ///< the layers' surfaces (tissue node indices)
  /// A reduced tissue's step refreshes the surface vertices within the needle's length plus
  /// this margin of its base (the needle reaches no others before the next tissue step).
  double surface_reach_margin_m = 0.03;
  /// Local tissue compliance seen by a constraint point (m/N), and the Gaussian
  /// correlation length of the coupling between points (Dequidt's wall compliance). With a
  /// reduced tissue the point compliance is what the basis misses (see NeedleTissueModel).
  double point_compliance_m_per_n = 2e-3;
  double compliance_correlation_length_m = 5e-3;
  /// Coulomb coefficient of the shaft on the lateral path forces (adds to the per-length limit).
  double shaft_friction_coefficient = 0.1;
  /// Distance between path constraints along the needle (slightly more than an element).
  double path_spacing_m = 0.01;
  int max_path_points = 32;
  /// Re-entering a punctured surface within this distance of the hole does not puncture again.
  double hole_radius_m = 2e-3;
  /// The bevel's lateral tip force (needle steering): the tip is pushed towards the bevel's
  /// open side (tip frame +y) by tan(tilt) times the cutting force, with tilt =
  /// bevel_steering_gain * (pi/2 - bevel angle). The gain is to be calibrated on a
  /// single-bend insertion.
  bool bevel_steering = false;
  double bevel_steering_gain = 0.5;
  int gauss_seidel_sweeps = 30;
  /// The instruction set of the Gauss-Seidel lane kernels (same bits in every one); `best`
  /// is the widest this CPU runs (nav/core/kernel_isa.hpp).
  KernelIsa kernel_isa = KernelIsa::best;
  /// A solve that ends with a larger law violation raises solver_not_converged.
  double residual_bound_m = 1e-5;
};

}  // namespace nav
