#include "nav/calibration/surface_icp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "nav/calibration/point_registration.hpp"

namespace nav::calibration {
namespace {

Eigen::Vector3d vertex(const TriSurface& surface, std::int32_t index) {
  const Point3& p = surface.vertices_m[static_cast<std::size_t>(index)];
  return {p[0], p[1], p[2]};
}

/// The surface's closest points: nearest vertex by brute force, then the exact closest point
/// over the triangles that share it.
class ClosestPoints {
 public:
  explicit ClosestPoints(const TriSurface& surface)
      : surface_(surface), triangles_of_vertex_(surface.vertices_m.size()) {
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
      for (std::int32_t v : surface.triangles[t]) triangles_of_vertex_[static_cast<std::size_t>(v)].push_back(t);
    }
  }

  Eigen::Vector3d closest(const Eigen::Vector3d& p) const {
    std::size_t nearest = 0;
    double nearest_squared = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < surface_.vertices_m.size(); ++v) {
      const Point3& q = surface_.vertices_m[v];
      const double d = (p - Eigen::Vector3d(q[0], q[1], q[2])).squaredNorm();
      if (d < nearest_squared) {
        nearest_squared = d;
        nearest = v;
      }
    }
    Eigen::Vector3d best = vertex(surface_, static_cast<std::int32_t>(nearest));
    for (std::size_t t : triangles_of_vertex_[nearest]) {
      const auto& tri = surface_.triangles[t];
      const Eigen::Vector3d candidate =
          closest_point_on_triangle(p, vertex(surface_, tri[0]), vertex(surface_, tri[1]), vertex(surface_, tri[2]));
      if ((candidate - p).squaredNorm() < (best - p).squaredNorm()) best = candidate;
    }
    return best;
  }

 private:
  const TriSurface& surface_;
  std::vector<std::vector<std::size_t>> triangles_of_vertex_;
};

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c) {
  // Ericson, Real-Time Collision Detection, 5.1.5: Voronoi regions of the vertices and edges.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

Result<IcpResult> surface_icp(const TriSurface& surface, const std::vector<Eigen::Vector3d>& points,
                              const Transform& initial, const IcpOptions& options) {
  if (surface.triangles.empty()) return Error{.message = "the surface has no triangles", .field = "surface"};
  if (points.size() < 6)
    return Error{.message = "too few points: " + std::to_string(points.size()) + " < 6", .field = "points"};
  if (point_spread(points)(2) < 1e-6) {
    return Error{.message = "the points are coplanar: they could slide within their plane", .field = "points"};
  }
  const ClosestPoints closest(surface);
  IcpResult result;
  result.surface_from_points = initial;
  double previous_rms = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3d> matches(points.size());
  for (result.iterations = 1; result.iterations <= options.max_iterations; ++result.iterations) {
    double sum_squares = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d moved = result.surface_from_points * points[i];
      matches[i] = closest.closest(moved);
      sum_squares += (matches[i] - moved).squaredNorm();
    }
    result.rms_distance_m = std::sqrt(sum_squares / static_cast<double>(points.size()));
    if (previous_rms - result.rms_distance_m < options.convergence_m) break;
    previous_rms = result.rms_distance_m;
    Result<PointRegistration> step = register_points(points, matches);
    if (!step) return step.error();
    result.surface_from_points = step.value().target_from_source;
  }
  result.iterations = std::min(result.iterations, options.max_iterations);
  return result;
}

}  // namespace nav::calibration
