#include "nav/mesher/embedded_liver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "nav/mesher/implicit_domain.hpp"
#include "nav/mesher/liver_shape.hpp"
#include "nav/mesher/mesher.hpp"

namespace nav {
namespace {

/// Half-width of the ligament bands: at least one row of nodes at any element size.
double band_half_width_m(double element_size_m) { return std::max(0.008, 0.75 * element_size_m); }

/// A surface facing up at least this much (normal's z) is the upper, diaphragmatic surface.
constexpr double kUpperNormalZ = 0.3;
/// The coronary ligament runs where the surface faces posteriorly and up, within ~25 degrees.
constexpr double kCoronaryCosine = 0.9;

/// Boundary nodes of the hilum and the ligaments, ascending.
std::vector<std::int32_t> attachment_nodes(const TetMesh& mesh, const std::vector<std::int32_t>& boundary_nodes,
                                           const ImplicitDomain& liver, const LiverLandmarks& landmarks,
                                           double element_size_m) {
  const Point3 down{0.0, 0.0, -1.0};
  const Point3 hilum_m = liver.crossing_along(landmarks.above_hilum_m, down, 1.0).value_or(landmarks.above_hilum_m);
  const double half = std::sqrt(0.5);
  const Point3 posterior_up{0.0, -half, half};
  std::vector<std::int32_t> nodes;
  for (const std::int32_t n : boundary_nodes) {
    const Point3& p = mesh.nodes_m[n];
    const Point3 g = liver.gradient(p);
    const Point3 normal = (1.0 / norm(g)) * g;
    const bool hilum = norm(p - hilum_m) <= landmarks.hilum_radius_m;
    const bool falciform = std::abs(p[0] - landmarks.falciform_x_m) <= band_half_width_m(element_size_m) &&
                           normal[2] >= kUpperNormalZ && p[1] >= landmarks.falciform_from_y_m;
    const bool coronary = dot(normal, posterior_up) >= kCoronaryCosine;
    if (hilum || falciform || coronary) nodes.push_back(n);
  }
  return nodes;
}

}  // namespace

EmbeddedLiver make_embedded_liver(double element_size_m) {
  const ImplicitDomain liver = make_liver_domain();
  const LiverLandmarks landmarks;
  auto made = make_tet_mesh(liver, {.element_size_m = element_size_m, .fitting = {}});
  if (!made.ok()) throw std::invalid_argument("embedded liver: " + made.error().describe());
  EmbeddedLiver result{std::move(made.value().mesh), landmarks.tumour_centre_m, landmarks.tumour_radius_m, {}};
  TetMesh& mesh = result.mesh;
  mesh.tet_regions.resize(mesh.tets.size());
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto& t = mesh.tets[e];
    const Point3 centroid = 0.25 * (mesh.nodes_m[t[0]] + mesh.nodes_m[t[1]] + mesh.nodes_m[t[2]] + mesh.nodes_m[t[3]]);
    const bool tumour = norm(centroid - landmarks.tumour_centre_m) < landmarks.tumour_radius_m;
    mesh.tet_regions[e] = static_cast<std::int32_t>(tumour ? TissueRegion::tumour : TissueRegion::parenchyma);
  }
  result.attachment_nodes = attachment_nodes(mesh, made.value().boundary_nodes, liver, landmarks, element_size_m);
  return result;
}

}  // namespace nav
