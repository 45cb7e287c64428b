#pragma once
// A bounding-volume hierarchy over a tissue surface's triangles, for the needle's layers: its
// layout is fixed at init (median splits on the rest positions), its boxes are refitted to the
// tissue's current positions after each tissue step, and it answers the nearest surface point
// with its side (the angle-weighted pseudo-normal of Baerentzen and Aanaes, exact for a closed
// surface). Internal to rtlib/nav/needle; refit and queries are allocation-free.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/needle/needle_tissue_scene.hpp"

namespace nav::detail {

/// One node of the hierarchy: a leaf holds `count` triangles from `first`; an inner node
/// (count 0) has its two children at `first` and `first + 1`, after it in the node order.
struct SurfaceBvhNode {
  std::int32_t first = 0;
  std::int32_t count = 0;
};

/// The immutable hierarchy of one TissueSurface.
struct SurfaceBvh {
  std::vector<std::array<std::int32_t, 3>> triangles;         ///< tissue nodes, in leaf order
  std::vector<std::array<std::int32_t, 3>> corners;           ///< the same corners as surface vertices
  std::vector<std::array<std::int32_t, 3>> neighbours;        ///< the triangle across edge k (corners k, k+1), or -1
  std::vector<std::int32_t> vertex_nodes;                     ///< tissue node of each surface vertex
  std::vector<std::int32_t> vertex_face_begin, vertex_faces;  ///< triangles around each vertex
  std::vector<SurfaceBvhNode> nodes;                          ///< the root first; parents before children
  std::size_t box_offset = 0;  ///< its boxes' first value in NeedleTissueData::surface_boxes (6 per node)
};

/// The nearest point of a surface to a query point, its outward (pseudo-)normal there, and
/// the query's signed distance: negative inside.
struct SurfaceHit {
  double distance_m = 0.0;
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

/// Builds the hierarchy of `surface` on the tissue's rest positions (3 per node); the Error
/// names a triangle whose node is out of range, at `field`.
Result<SurfaceBvh> make_surface_bvh(const TissueSurface& surface, std::span<const double> tissue_rest_m,
                                    const std::string& field);

/// Refits the boxes (6 per node: lower then upper corner) to the current positions, rest plus
/// displacements (3 per node; empty: at rest).
void refit_surface_bvh(const SurfaceBvh& bvh, std::span<double> boxes, std::span<const double> rest_m,
                       std::span<const double> displacements_m) noexcept;

/// The surface point nearest `x_m` at the current positions (the boxes refitted to them).
SurfaceHit nearest_surface_point(const SurfaceBvh& bvh, std::span<const double> boxes, std::span<const double> rest_m,
                                 std::span<const double> displacements_m, const Eigen::Vector3d& x_m) noexcept;

}  // namespace nav::detail
