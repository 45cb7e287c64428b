#include "nav/mesher/boundary_fitting.hpp"

#include <algorithm>

#include "nav/mesher/crease.hpp"
#include "nav/mesher/guarded_node_mover.hpp"
#include "nav/mesher/node_adjacency.hpp"

namespace nav {
namespace {

/// Smoothing only accepts moves that keep the smallest radius ratio around the node.
constexpr double kNoQualityLoss = 1.0;

/// Distance from `point_m` to its projection on the domain's boundary.
double gap_m(const MeshingDomain& domain, const Point3& point_m) {
  return norm(domain.project_to_boundary(point_m) - point_m);
}

/// The nodes, neighbours and state that fitting works on.
class Fitter {
 public:
  Fitter(TetMesh& mesh, const BoundaryToFit& boundary, const FittingOptions& options)
      : mesh_(mesh),
        boundary_(boundary),
        options_(options),
        mover_(mesh),
        neighbours_(neighbours_of_nodes(mesh)),
        faces_of_node_(faces_of_nodes(boundary.faces, mesh.nodes_m.size())),
        on_boundary_(mesh.nodes_m.size(), 0) {
    for (const std::int32_t n : boundary_.nodes) {
      on_boundary_[n] = gap_m(*boundary_.domain, mesh_.nodes_m[n]) <= options_.snapped_tolerance_m;
    }
  }

  /// One sweep over the boundary nodes, pulled towards their neighbours by `relaxation`.
  void snap(double relaxation) {
    for (const std::int32_t n : boundary_.nodes) {
      const Point3 p = mesh_.nodes_m[n];
      const Point3 foot = boundary_.domain->project_to_boundary(p);
      on_boundary_[n] = norm(foot - p) <= options_.snapped_tolerance_m;
      if (on_boundary_[n] && (relaxation == 0.0 || on_crease(n))) continue;
      Point3 sum{};
      int count = 0;
      for (const std::int32_t m : neighbours_.of(n)) {
        if (!std::binary_search(boundary_.nodes.begin(), boundary_.nodes.end(), m)) continue;
        sum = sum + mesh_.nodes_m[m];
        ++count;
      }
      const Point3 pulled = count > 0 ? p + (relaxation / count) * (sum - static_cast<double>(count) * p) : p;
      const Point3 target = count > 0 ? boundary_.domain->project_to_boundary(pulled) : foot;
      on_boundary_[n] = mover_.move_towards(n, target, options_.quality_floor, options_.max_halvings) == 1.0;
    }
  }

  /// One sweep of guarded Laplacian smoothing over the interior nodes.
  void smooth() {
    for (std::size_t n = 0; n < mesh_.nodes_m.size(); ++n) {
      const auto node = static_cast<std::int32_t>(n);
      const auto around = neighbours_.of(node);
      if (around.empty() || std::binary_search(boundary_.nodes.begin(), boundary_.nodes.end(), node)) continue;
      Point3 sum{};
      for (const std::int32_t m : around) sum = sum + mesh_.nodes_m[m];
      mover_.move_towards(node, (1.0 / static_cast<double>(around.size())) * sum, kNoQualityLoss,
                          options_.max_halvings);
    }
  }

 private:
  /// True if, among the boundary faces around `node` whose nodes are all on the domain's
  /// boundary, two bend by more than the crease angle.
  bool on_crease(std::int32_t node) const {
    std::vector<Point3> normals;
    for (const std::int32_t f : faces_of_node_.of(node)) {
      const auto& face = boundary_.faces[f];
      if (!on_boundary_[face[0]] || !on_boundary_[face[1]] || !on_boundary_[face[2]]) continue;
      const Point3& a = mesh_.nodes_m[face[0]];
      normals.push_back(cross(mesh_.nodes_m[face[1]] - a, mesh_.nodes_m[face[2]] - a));
    }
    return bends_into_crease(normals, options_.crease_cosine);
  }

  TetMesh& mesh_;
  const BoundaryToFit& boundary_;
  const FittingOptions& options_;
  GuardedNodeMover mover_;
  NodeLists neighbours_;
  NodeLists faces_of_node_;
  std::vector<std::uint8_t> on_boundary_;  ///< per node, as last seen
};

}  // namespace

FittingReport fit_to_boundary(TetMesh& mesh, const BoundaryToFit& boundary, const FittingOptions& options) {
  Fitter fitter(mesh, boundary, options);
  for (int pass = 0; pass < options.passes; ++pass) {
    fitter.snap(options.relaxation);
    for (int sweep = 0; sweep < options.smoothing_sweeps; ++sweep) fitter.smooth();
  }
  // Straight onto the boundary: the nodes the smoothing made room for, those a halved move left short.
  fitter.snap(0.0);

  FittingReport report;
  for (const std::int32_t n : boundary.nodes) {
    const double gap = gap_m(*boundary.domain, mesh.nodes_m[n]);
    report.max_gap_m = std::max(report.max_gap_m, gap);
    if (gap > options.snapped_tolerance_m) report.unsnapped_nodes.push_back(n);
  }
  return report;
}

}  // namespace nav
