#include "nav/mesher/distance_transform.hpp"

#include <cmath>
#include <limits>

namespace nav {
namespace {

/// Stands for "no feature": large, but finite so that the envelope arithmetic stays exact.
constexpr double kFar = 1e20;

/// In place along one line: squared[q] becomes min over p of ((q - p) spacing)^2 + squared[p].
void squared_distance_1d(std::vector<double>& squared, double spacing_m, std::vector<std::int64_t>& vertex,
                         std::vector<double>& boundary) {
  const auto n = static_cast<std::int64_t>(squared.size());
  const std::vector<double> f = squared;
  vertex.assign(static_cast<std::size_t>(n), 0);
  boundary.assign(static_cast<std::size_t>(n + 1), 0.0);
  const auto x = [spacing_m](std::int64_t q) { return static_cast<double>(q) * spacing_m; };
  // Lower envelope of the parabolas y = (t - x(p))^2 + f[p].
  std::int64_t k = 0;
  boundary[0] = -std::numeric_limits<double>::infinity();
  boundary[1] = std::numeric_limits<double>::infinity();
  const auto meet = [&](std::int64_t q, std::int64_t p) {
    return ((f[q] + x(q) * x(q)) - (f[p] + x(p) * x(p))) / (2.0 * (x(q) - x(p)));
  };
  for (std::int64_t q = 1; q < n; ++q) {
    // boundary[0] is -infinity, so this stops at k = 0 at the latest.
    double t = meet(q, vertex[static_cast<std::size_t>(k)]);
    while (t <= boundary[static_cast<std::size_t>(k)]) t = meet(q, vertex[static_cast<std::size_t>(--k)]);
    ++k;
    vertex[static_cast<std::size_t>(k)] = q;
    boundary[static_cast<std::size_t>(k)] = t;
    boundary[static_cast<std::size_t>(k + 1)] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (std::int64_t q = 0; q < n; ++q) {
    while (boundary[static_cast<std::size_t>(k + 1)] < x(q)) ++k;
    const std::int64_t p = vertex[static_cast<std::size_t>(k)];
    squared[static_cast<std::size_t>(q)] = (x(q) - x(p)) * (x(q) - x(p)) + f[p];
  }
}

/// Squared distance from every sample to the nearest sample where `feature` is set.
std::vector<double> squared_distance_map(const std::vector<std::uint8_t>& feature,
                                         const std::array<std::int64_t, 3>& size, const Point3& spacing_m) {
  std::vector<double> squared(feature.size());
  for (std::size_t i = 0; i < feature.size(); ++i) squared[i] = feature[i] ? 0.0 : kFar;
  const std::int64_t strides[3] = {1, size[0], size[0] * size[1]};
  std::vector<double> line;
  std::vector<std::int64_t> vertex;
  std::vector<double> boundary;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    for (std::int64_t b = 0; b < size[v]; ++b) {
      for (std::int64_t a = 0; a < size[u]; ++a) {
        const std::int64_t start = a * strides[u] + b * strides[v];
        line.resize(static_cast<std::size_t>(size[axis]));
        for (std::int64_t q = 0; q < size[axis]; ++q)
          line[static_cast<std::size_t>(q)] = squared[static_cast<std::size_t>(start + q * strides[axis])];
        squared_distance_1d(line, spacing_m[axis], vertex, boundary);
        for (std::int64_t q = 0; q < size[axis]; ++q)
          squared[static_cast<std::size_t>(start + q * strides[axis])] = line[static_cast<std::size_t>(q)];
      }
    }
  }
  return squared;
}

}  // namespace

std::vector<float> signed_distance_map_m(const std::vector<std::uint8_t>& inside,
                                         const std::array<std::int64_t, 3>& size, const Point3& spacing_m) {
  std::vector<std::uint8_t> outside(inside.size());
  for (std::size_t i = 0; i < inside.size(); ++i) outside[i] = inside[i] ? 0 : 1;
  const std::vector<double> to_outside = squared_distance_map(outside, size, spacing_m);
  const std::vector<double> to_inside = squared_distance_map(inside, size, spacing_m);
  std::vector<float> distance(inside.size());
  for (std::size_t i = 0; i < inside.size(); ++i) {
    const double squared = inside[i] ? to_outside[i] : to_inside[i];
    const double magnitude = squared >= kFar ? 1e10 : std::sqrt(squared);
    distance[i] = static_cast<float>(inside[i] ? -magnitude : magnitude);
  }
  return distance;
}

}  // namespace nav
