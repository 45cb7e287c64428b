#include "nav/connective/organ_attachment.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "nav/mesh/geometry.hpp"

namespace nav {

Result<std::pair<std::int32_t, std::array<double, 4>>> locate_in_tets(const TetMesh& mesh, const Point3& point_m,
                                                                      const std::string& field) {
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    std::array<Point3, 4> c;
    for (int a = 0; a < 4; ++a) c[a] = mesh.nodes_m[static_cast<std::size_t>(mesh.tets[e][a])];
    const double volume = signed_tet_volume_m3(c[0], c[1], c[2], c[3]);
    if (!(std::abs(volume) > 0.0)) continue;
    std::array<double, 4> b{};
    bool inside = true;
    for (int a = 0; a < 4 && inside; ++a) {
      std::array<Point3, 4> replaced = c;
      replaced[a] = point_m;
      b[a] = signed_tet_volume_m3(replaced[0], replaced[1], replaced[2], replaced[3]) / volume;
      inside = b[a] >= -1e-9;
    }
    if (inside) return std::make_pair(static_cast<std::int32_t>(e), b);
  }
  return Error{.message = "the point (" + std::to_string(point_m[0]) + ", " + std::to_string(point_m[1]) + ", " +
                          std::to_string(point_m[2]) + ") m is in no tetrahedron of the organ",
               .field = field};
}

namespace {

/// k_s: the tissue's translational stiffness at rest on each driven frame (the largest
/// diagonal entry of K), lumped on the nodes by the barycentric weights; the largest.
double stabilising_spring_n_m(const FrameTissueModel& tissue, const OrganAttachment& attachment) {
  auto data = make_frame_tissue_data(tissue);
  if (!data.ok()) return 0.0;
  const auto dofs = static_cast<std::size_t>(6 * tissue.frame_count());
  std::vector<double> forces(dofs), unit(dofs, 0.0), product(dofs);
  elastic_forces(tissue, data.value(), forces);
  std::vector<double> node_stiffness(attachment.nodes.size(), 0.0);
  for (std::size_t d = 0; d < attachment.corners.size(); ++d) {
    double stiffness = 0.0;
    for (std::size_t a = 0; a < 3; ++a) {
      const std::size_t k = 6 * static_cast<std::size_t>(tissue.driven_frames()[d]) + a;
      unit[k] = 1.0;
      stiffness_product(tissue, data.value(), unit, product);
      unit[k] = 0.0;
      stiffness = std::max(stiffness, product[k]);
    }
    for (int c = 0; c < 4; ++c)
      node_stiffness[static_cast<std::size_t>(attachment.slots[d][c])] += attachment.barycentric[d][c] * stiffness;
  }
  return node_stiffness.empty() ? 0.0 : *std::max_element(node_stiffness.begin(), node_stiffness.end());
}

}  // namespace

Result<OrganAttachment> attach_driven_frames(const FrameTissueModel& tissue, const TetMesh& organ, bool stabilise) {
  OrganAttachment attachment;
  const std::span<const double> rest = tissue.rest_positions_m();
  for (std::int32_t f : tissue.driven_frames()) {
    const auto i = static_cast<std::size_t>(f);
    auto located =
        locate_in_tets(organ, {rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]}, "driven frame " + std::to_string(f));
    if (!located.ok()) return located.error();
    attachment.corners.push_back(organ.tets[static_cast<std::size_t>(located.value().first)]);
    attachment.barycentric.push_back(located.value().second);
    for (std::int32_t node : attachment.corners.back()) attachment.nodes.push_back(node);
  }
  std::sort(attachment.nodes.begin(), attachment.nodes.end());
  attachment.nodes.erase(std::unique(attachment.nodes.begin(), attachment.nodes.end()), attachment.nodes.end());
  for (const auto& corners : attachment.corners) {
    std::array<std::int32_t, 4> slots{};
    for (int a = 0; a < 4; ++a)
      slots[a] = static_cast<std::int32_t>(
          std::lower_bound(attachment.nodes.begin(), attachment.nodes.end(), corners[a]) - attachment.nodes.begin());
    attachment.slots.push_back(slots);
  }
  for (std::int32_t node : attachment.nodes)
    for (double c : organ.nodes_m[static_cast<std::size_t>(node)]) attachment.node_rest_positions_m.push_back(c);
  if (stabilise) attachment.spring_stiffness_n_m = stabilising_spring_n_m(tissue, attachment);
  return attachment;
}

void declare_attachment(const OrganAttachment& attachment, TissueScene& organ_scene) {
  organ_scene.max_point_forces += attachment.nodes.size();
  if (!(attachment.spring_stiffness_n_m > 0.0)) return;
  organ_scene.spring_nodes = attachment.nodes;
  organ_scene.spring_stiffness_n_m = attachment.spring_stiffness_n_m;
}

AttachmentBuffers make_attachment_buffers(const OrganAttachment& attachment) {
  AttachmentBuffers buffers;
  buffers.driven_positions_m.assign(3 * attachment.corners.size(), 0.0);
  for (std::int32_t node : attachment.nodes) buffers.point_forces.push_back({node, {}});
  return buffers;
}

void gather_attachment_positions(const OrganAttachment& attachment, std::span<const double> organ_positions_m,
                                 std::span<double> driven_positions_m) noexcept {
  for (std::size_t d = 0; d < attachment.corners.size(); ++d)
    for (std::size_t a = 0; a < 3; ++a) {
      double x = 0.0;
      for (int k = 0; k < 4; ++k)
        x += attachment.barycentric[d][k] *
             organ_positions_m[3 * static_cast<std::size_t>(attachment.corners[d][k]) + a];
      driven_positions_m[3 * d + a] = x;
    }
}

void scatter_attachment_forces(const OrganAttachment& attachment, std::span<const double> driven_forces_n,
                               std::span<const double> organ_positions_m, std::span<PointForce> point_forces) noexcept {
  for (std::size_t n = 0; n < attachment.nodes.size(); ++n) {
    point_forces[n] = {attachment.nodes[n], {0.0, 0.0, 0.0}};
    for (std::size_t a = 0; a < 3; ++a)
      point_forces[n].force_n[a] =
          attachment.spring_stiffness_n_m * (organ_positions_m[3 * static_cast<std::size_t>(attachment.nodes[n]) + a] -
                                             attachment.node_rest_positions_m[3 * n + a]);
  }
  for (std::size_t d = 0; d < attachment.corners.size(); ++d)
    for (int k = 0; k < 4; ++k)
      for (std::size_t a = 0; a < 3; ++a)
        point_forces[static_cast<std::size_t>(attachment.slots[d][k])].force_n[a] +=
            attachment.barycentric[d][k] * driven_forces_n[3 * d + a];
}

void step_attached(const FrameTissueModel& tissue, FrameTissueData& data, const OrganAttachment& attachment,
                   AttachmentBuffers& buffers, std::span<const double> organ_positions_m, double load_scale) noexcept {
  gather_attachment_positions(attachment, organ_positions_m, buffers.driven_positions_m);
  FrameTissueInputs inputs;
  inputs.load_scale = load_scale;
  inputs.driven_positions_m = buffers.driven_positions_m;
  step(tissue, data, inputs);
  scatter_attachment_forces(attachment, data.driven_forces_n, organ_positions_m, buffers.point_forces);
}

}  // namespace nav
