#include "nav/needle/surface_bvh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>

namespace nav::detail {

namespace {

/// Triangles per leaf at most.
constexpr std::size_t kLeafTriangles = 4;
/// Room of the query's stack: a median-split hierarchy is at most log2(triangles) deep.
constexpr std::size_t kStackDepth = 64;

Eigen::Vector3d position_m(std::span<const double> rest_m, std::span<const double> displacements_m, std::int32_t node) {
  const auto at = 3 * static_cast<std::size_t>(node);
  Eigen::Vector3d p(rest_m[at], rest_m[at + 1], rest_m[at + 2]);
  if (!displacements_m.empty())
    p += Eigen::Vector3d(displacements_m[at], displacements_m[at + 1], displacements_m[at + 2]);
  return p;
}

/// Where on a triangle its nearest point to a query lies: inside (kind 0), on edge `index`
/// (corners index and index + 1; kind 1) or at corner `index` (kind 2).
struct TrianglePoint {
  Eigen::Vector3d point_m;
  int kind = 0;
  int index = 0;
};

/// The nearest point of triangle (a, b, c) to p, by its Voronoi regions (Ericson, Real-Time
/// Collision Detection, 5.1.5). A degenerate triangle answers its first corner.
TrianglePoint nearest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, 2, 0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, 2, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {a + d1 / (d1 - d3) * ab, 1, 0};
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, 2, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {a + d2 / (d2 - d6) * ac, 1, 2};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) return {b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b), 1, 1};
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return {a, 2, 0};
  return {a + (vb / sum) * ab + (vc / sum) * ac, 0, 0};
}

struct Corners {
  Eigen::Vector3d p[3];
};

Corners corners_m(const SurfaceBvh& bvh, std::size_t triangle, std::span<const double> rest_m,
                  std::span<const double> displacements_m) {
  const auto& t = bvh.triangles[triangle];
  return {{position_m(rest_m, displacements_m, t[0]), position_m(rest_m, displacements_m, t[1]),
           position_m(rest_m, displacements_m, t[2])}};
}

/// The unit normal of a triangle (zero when degenerate).
Eigen::Vector3d face_normal(const Corners& c) {
  const Eigen::Vector3d n = (c.p[1] - c.p[0]).cross(c.p[2] - c.p[0]);
  const double length = n.norm();
  return length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
}

/// The pseudo-normal of the feature `at` of `triangle`: its face normal inside, the sum of the
/// two faces' normals on an edge, the angle-weighted sum of the faces' around a corner.
Eigen::Vector3d pseudo_normal(const SurfaceBvh& bvh, std::size_t triangle, const TrianglePoint& at,
                              std::span<const double> rest_m, std::span<const double> displacements_m) {
  const Eigen::Vector3d own = face_normal(corners_m(bvh, triangle, rest_m, displacements_m));
  if (at.kind == 0) return own;
  if (at.kind == 1) {
    const std::int32_t other = bvh.neighbours[triangle][static_cast<std::size_t>(at.index)];
    if (other < 0) return own;
    return own + face_normal(corners_m(bvh, static_cast<std::size_t>(other), rest_m, displacements_m));
  }
  const std::int32_t vertex = bvh.corners[triangle][static_cast<std::size_t>(at.index)];
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (auto k = static_cast<std::size_t>(bvh.vertex_face_begin[static_cast<std::size_t>(vertex)]);
       k < static_cast<std::size_t>(bvh.vertex_face_begin[static_cast<std::size_t>(vertex) + 1]); ++k) {
    const auto face = static_cast<std::size_t>(bvh.vertex_faces[k]);
    const Corners c = corners_m(bvh, face, rest_m, displacements_m);
    int corner = 0;
    while (corner < 2 && bvh.corners[face][static_cast<std::size_t>(corner)] != vertex) ++corner;
    const Eigen::Vector3d e1 = c.p[(corner + 1) % 3] - c.p[corner], e2 = c.p[(corner + 2) % 3] - c.p[corner];
    const double lengths = e1.norm() * e2.norm();
    if (!(lengths > 0.0)) continue;
    sum += std::acos(std::clamp(e1.dot(e2) / lengths, -1.0, 1.0)) * face_normal(c);
  }
  return sum;
}

double box_distance2(std::span<const double> box, const Eigen::Vector3d& x) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double below = box[static_cast<std::size_t>(c)] - x[c], above = x[c] - box[static_cast<std::size_t>(c) + 3];
    const double outside = std::max({below, above, 0.0});
    sum += outside * outside;
  }
  return sum;
}

/// Splits triangles [begin, end) of `order` under node `node` at the median of their
/// centroids along the longest axis of the centroids' box (ties by index), recursively.
void split(SurfaceBvh& bvh, std::vector<std::int32_t>& order, const std::vector<Eigen::Vector3d>& centroids,
           std::size_t node, std::size_t begin, std::size_t end) {
  if (end - begin <= kLeafTriangles) {
    bvh.nodes[node] = {static_cast<std::int32_t>(begin), static_cast<std::int32_t>(end - begin)};
    return;
  }
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (std::size_t k = begin; k < end; ++k) {
    low = low.cwiseMin(centroids[static_cast<std::size_t>(order[k])]);
    high = high.cwiseMax(centroids[static_cast<std::size_t>(order[k])]);
  }
  int axis = 0;
  (high - low).maxCoeff(&axis);
  std::sort(order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(end),
            [&](std::int32_t a, std::int32_t b) {
              const double ka = centroids[static_cast<std::size_t>(a)][axis];
              const double kb = centroids[static_cast<std::size_t>(b)][axis];
              return ka < kb || (ka == kb && a < b);
            });
  const std::size_t children = bvh.nodes.size(), middle = begin + (end - begin) / 2;
  bvh.nodes.resize(children + 2);
  bvh.nodes[node] = {static_cast<std::int32_t>(children), 0};
  split(bvh, order, centroids, children, begin, middle);
  split(bvh, order, centroids, children + 1, middle, end);
}

/// Vertices, corners, neighbours across edges and the triangles around each vertex.
void connect(SurfaceBvh& bvh) {
  for (const auto& t : bvh.triangles) bvh.vertex_nodes.insert(bvh.vertex_nodes.end(), t.begin(), t.end());
  std::sort(bvh.vertex_nodes.begin(), bvh.vertex_nodes.end());
  bvh.vertex_nodes.erase(std::unique(bvh.vertex_nodes.begin(), bvh.vertex_nodes.end()), bvh.vertex_nodes.end());
  const std::size_t triangles = bvh.triangles.size(), vertices = bvh.vertex_nodes.size();
  bvh.corners.resize(triangles);
  bvh.vertex_face_begin.assign(vertices + 1, 0);
  for (std::size_t t = 0; t < triangles; ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto found = std::lower_bound(bvh.vertex_nodes.begin(), bvh.vertex_nodes.end(), bvh.triangles[t][k]);
      bvh.corners[t][k] = static_cast<std::int32_t>(found - bvh.vertex_nodes.begin());
      ++bvh.vertex_face_begin[static_cast<std::size_t>(bvh.corners[t][k]) + 1];
    }
  std::partial_sum(bvh.vertex_face_begin.begin(), bvh.vertex_face_begin.end(), bvh.vertex_face_begin.begin());
  bvh.vertex_faces.resize(3 * triangles);
  std::vector<std::int32_t> filled(bvh.vertex_face_begin.begin(), bvh.vertex_face_begin.end() - 1);
  for (std::size_t t = 0; t < triangles; ++t)
    for (const std::int32_t v : bvh.corners[t])
      bvh.vertex_faces[static_cast<std::size_t>(filled[static_cast<std::size_t>(v)]++)] = static_cast<std::int32_t>(t);
  // Edges as (lower vertex, higher vertex, triangle, edge): an edge of exactly two triangles
  // joins them; a boundary or non-manifold edge has no neighbour.
  struct Edge {
    std::int32_t low, high, triangle, edge;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * triangles);
  for (std::size_t t = 0; t < triangles; ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::int32_t a = bvh.corners[t][k], b = bvh.corners[t][(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<std::int32_t>(t), static_cast<std::int32_t>(k)});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return std::tie(x.low, x.high, x.triangle, x.edge) < std::tie(y.low, y.high, y.triangle, y.edge);
  });
  bvh.neighbours.assign(triangles, {-1, -1, -1});
  for (std::size_t first = 0; first < edges.size();) {
    std::size_t last = first + 1;
    while (last < edges.size() && edges[last].low == edges[first].low && edges[last].high == edges[first].high) ++last;
    if (last - first == 2) {
      const Edge& x = edges[first];
      const Edge& y = edges[first + 1];
      bvh.neighbours[static_cast<std::size_t>(x.triangle)][static_cast<std::size_t>(x.edge)] = y.triangle;
      bvh.neighbours[static_cast<std::size_t>(y.triangle)][static_cast<std::size_t>(y.edge)] = x.triangle;
    }
    first = last;
  }
}

}  // namespace

Result<SurfaceBvh> make_surface_bvh(const TissueSurface& surface, std::span<const double> tissue_rest_m,
                                    const std::string& field) {
  const std::size_t nodes = tissue_rest_m.size() / 3;
  if (surface.triangles.empty()) return Error{.message = "has no triangles", .field = field};
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    for (const std::int32_t node : surface.triangles[t])
      if (node < 0 || static_cast<std::size_t>(node) >= nodes)
        return Error{.message = "triangle " + std::to_string(t) + " names node " + std::to_string(node) +
                                ", beyond the tissue's " + std::to_string(nodes) + " nodes",
                     .field = field};
  std::vector<Eigen::Vector3d> centroids;
  centroids.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles)
    centroids.push_back((position_m(tissue_rest_m, {}, t[0]) + position_m(tissue_rest_m, {}, t[1]) +
                         position_m(tissue_rest_m, {}, t[2])) /
                        3.0);
  std::vector<std::int32_t> order(surface.triangles.size());
  std::iota(order.begin(), order.end(), 0);
  SurfaceBvh bvh;
  bvh.nodes.resize(1);
  split(bvh, order, centroids, 0, 0, order.size());
  for (const std::int32_t t : order) bvh.triangles.push_back(surface.triangles[static_cast<std::size_t>(t)]);
  connect(bvh);
  return bvh;
}

void refit_surface_bvh(const SurfaceBvh& bvh, std::span<double> boxes, std::span<const double> rest_m,
                       std::span<const double> displacements_m) noexcept {
  for (std::size_t n = bvh.nodes.size(); n-- > 0;) {
    const SurfaceBvhNode& node = bvh.nodes[n];
    const std::span<double> box = boxes.subspan(6 * n, 6);
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), high = -low;
    if (node.count > 0) {
      for (auto t = static_cast<std::size_t>(node.first); t < static_cast<std::size_t>(node.first + node.count); ++t)
        for (const std::int32_t v : bvh.triangles[t]) {
          const Eigen::Vector3d p = position_m(rest_m, displacements_m, v);
          low = low.cwiseMin(p);
          high = high.cwiseMax(p);
        }
    } else {
      for (std::size_t child = 0; child < 2; ++child) {
        const std::span<const double> inner = boxes.subspan(6 * (static_cast<std::size_t>(node.first) + child), 6);
        low = low.cwiseMin(Eigen::Vector3d(inner[0], inner[1], inner[2]));
        high = high.cwiseMax(Eigen::Vector3d(inner[3], inner[4], inner[5]));
      }
    }
    for (std::size_t c = 0; c < 3; ++c) {
      box[c] = low[static_cast<Eigen::Index>(c)];
      box[c + 3] = high[static_cast<Eigen::Index>(c)];
    }
  }
}

SurfaceHit nearest_surface_point(const SurfaceBvh& bvh, std::span<const double> boxes, std::span<const double> rest_m,
                                 std::span<const double> displacements_m, const Eigen::Vector3d& x_m) noexcept {
  std::array<std::int32_t, kStackDepth> stack{};
  std::size_t depth = 0;
  stack[depth++] = 0;
  double best_distance2 = std::numeric_limits<double>::infinity();
  std::size_t best_triangle = 0;
  TrianglePoint best{x_m, 0, 0};
  const auto box_of = [&](std::int32_t node) { return boxes.subspan(6 * static_cast<std::size_t>(node), 6); };
  while (depth > 0) {
    const std::int32_t n = stack[--depth];
    if (!(box_distance2(box_of(n), x_m) < best_distance2)) continue;
    const SurfaceBvhNode& node = bvh.nodes[static_cast<std::size_t>(n)];
    if (node.count > 0) {
      for (auto t = static_cast<std::size_t>(node.first); t < static_cast<std::size_t>(node.first + node.count); ++t) {
        const Corners c = corners_m(bvh, t, rest_m, displacements_m);
        const TrianglePoint at = nearest_on_triangle(x_m, c.p[0], c.p[1], c.p[2]);
        const double distance2 = (x_m - at.point_m).squaredNorm();
        if (distance2 < best_distance2) {
          best_distance2 = distance2;
          best_triangle = t;
          best = at;
        }
      }
      continue;
    }
    // The nearer child is searched first. A median-split hierarchy is far shallower than the
    // stack; were it full, both children would be skipped.
    const std::int32_t near = node.first, far = node.first + 1;
    const bool swap = box_distance2(box_of(far), x_m) < box_distance2(box_of(near), x_m);
    if (depth + 2 > stack.size()) continue;
    stack[depth++] = swap ? near : far;
    stack[depth++] = swap ? far : near;
  }
  SurfaceHit hit;
  hit.point_m = best.point_m;
  const Eigen::Vector3d normal = pseudo_normal(bvh, best_triangle, best, rest_m, displacements_m);
  const double length = normal.norm();
  if (length > 0.0) hit.normal = normal / length;
  const double distance = std::sqrt(best_distance2);
  hit.distance_m = hit.normal.dot(x_m - hit.point_m) < 0.0 ? -distance : distance;
  return hit;
}

}  // namespace nav::detail
