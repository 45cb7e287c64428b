#include "nav/station/station_liver.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "nav/mesh/load_mesh.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/training_loads.hpp"

namespace nav::station {

namespace {

constexpr double kDiaphragmDepthM = 0.02;  // boundary nodes this close to the top are the diaphragm

Error liver_error(const Scene& scene, const std::string& message, const std::string& field) {
  return Error{.message = message, .file = scene.source_path, .line = scene.liver.line, .field = field};
}

/// Boundary nodes within kDiaphragmDepthM of the top that are not attachments.
std::vector<std::int32_t> diaphragm_nodes(const TetMesh& mesh, const std::vector<std::int32_t>& attachments) {
  const TetMeshBoundary boundary = extract_boundary(mesh);
  double top_m = -1e9;
  for (const auto& x : mesh.nodes_m) top_m = std::max(top_m, x[2]);
  std::vector<char> on_boundary(mesh.nodes_m.size(), 0);
  for (const std::int32_t node : boundary.mesh_node_of_vertex) on_boundary[static_cast<std::size_t>(node)] = 1;
  std::vector<std::int32_t> nodes;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    if (on_boundary[n] != 0 && mesh.nodes_m[n][2] > top_m - kDiaphragmDepthM &&
        !std::binary_search(attachments.begin(), attachments.end(), static_cast<std::int32_t>(n)))
      nodes.push_back(static_cast<std::int32_t>(n));
  return nodes;
}

}  // namespace

Result<TetMesh> make_station_mesh(const Scene& scene) {
  if (scene.liver.mesh.source == LiverMeshSource::file) {
    auto mesh = load_tet_mesh(scene.liver.mesh.path, scene.liver.mesh.unit);
    if (!mesh.ok()) return liver_error(scene, mesh.error().describe(), "liver.mesh");
    return mesh;
  }
  try {
    return make_embedded_liver(scene.liver.mesh.element_size_m).mesh;
  } catch (const std::invalid_argument& e) {
    return liver_error(scene, e.what(), "liver.mesh.element_size_m");
  }
}

Result<StationLiver> make_station_liver(const Scene& scene) {
  const LiverSettings& settings = scene.liver;
  StationLiver liver;
  std::vector<std::int32_t> attachments;
  if (settings.mesh.source == LiverMeshSource::file) {
    auto mesh = make_station_mesh(scene);
    if (!mesh.ok()) return mesh.error();
    liver.mesh = std::move(mesh).value();
  } else {
    try {
      EmbeddedLiver generated = make_embedded_liver(settings.mesh.element_size_m);
      liver.mesh = std::move(generated.mesh);
      liver.tumour_m = generated.tumour_centre_m;
      attachments = std::move(generated.attachment_nodes);
    } catch (const std::invalid_argument& e) {
      return liver_error(scene, e.what(), "liver.mesh.element_size_m");
    }
  }
  if (settings.tumour_m) liver.tumour_m = *settings.tumour_m;
  const auto located = locate_in_tets(liver.mesh, liver.tumour_m, "tumour_m");
  if (!located.ok()) return liver_error(scene, "the tumour point lies outside the liver mesh", "liver.tumour_m");
  liver.tumour = {liver.mesh.tets[static_cast<std::size_t>(located.value().first)], located.value().second};
  if (settings.mesh.source == LiverMeshSource::generated && settings.rung == LiverRung::full) {
    liver.scene.fixed_nodes = attachments;
    liver.scene.prescribed_nodes = diaphragm_nodes(liver.mesh, attachments);
  } else {
    liver.scene = liver_reduction_scene(liver.mesh);
  }
  liver.scene.default_material = settings.material;
  liver.scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  return liver;
}

}  // namespace nav::station
