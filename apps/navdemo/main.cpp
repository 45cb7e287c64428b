// navdemo: the liver deformation demo (the first part of the README's demo command).
// Builds the embedded default liver with its tumour and attachments, solves its static
// deformation under gravity and under gravity plus an ultrasound probe pressing on the
// anterior surface above the tumour with the neo-Hookean model (the reference at these
// centimetre displacements), and beside it with linear FEM, the cheap rung, whose error against
// the reference it prints; writes both fields (and the linear error) as a .vtu.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "nav/core/units.hpp"
#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesh/vtu_writer.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/tissue/linear_elastic_static.hpp"
#include "nav/tissue/newton_static.hpp"

namespace {

constexpr int kExitBadInput = 2;

struct Options {
  double element_size_m = nav::kEmbeddedLiverElementSizeM;
  double probe_force_n = 3.0;
  double probe_radius_m = 0.015;
  std::string out_path = "liver_demo.vtu";
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool parse_options(int argc, char** argv, Options& options) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--out" && has_value) {
      options.out_path = argv[++i];
    } else if ((arg == "--size" || arg == "--probe-force") && has_value) {
      char* end = nullptr;
      const double value = std::strtod(argv[++i], &end);
      if (end == argv[i] || *end != '\0' || !(value > 0.0) || !std::isfinite(value)) {
        std::fprintf(stderr, "navdemo: %s: expected a positive number, got '%s'\n", arg.c_str(), argv[i]);
        return false;
      }
      (arg == "--size" ? options.element_size_m : options.probe_force_n) = value;
    } else {
      std::fprintf(stderr, "usage: navdemo [--size H_M] [--probe-force N] [--out FILE.vtu]\n");
      return false;
    }
  }
  return true;
}

/// Volume-weighted mean displacement of the tumour's elements (its centre's motion).
nav::Point3 tumour_displacement_m(const nav::TetMesh& mesh, const std::vector<nav::Point3>& displacement_m) {
  nav::Point3 sum{0.0, 0.0, 0.0};
  double volume_m3 = 0.0;
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    if (mesh.tet_regions[e] != static_cast<std::int32_t>(nav::TissueRegion::tumour)) continue;
    const double v = nav::signed_tet_volume_m3(mesh, e);
    for (std::int32_t node : mesh.tets[e]) sum = sum + (v / 4.0) * displacement_m[node];
    volume_m3 += v;
  }
  return volume_m3 > 0.0 ? (1.0 / volume_m3) * sum : sum;
}

/// The probe: `force_n` pushing posteriorly (-y), shared equally by the boundary nodes within
/// `radius_m` of the anterior boundary node right above the tumour.
std::vector<nav::PointForce> probe_forces(const nav::EmbeddedLiver& liver, double force_n, double radius_m) {
  const nav::TetMeshBoundary boundary = nav::extract_boundary(liver.mesh);
  std::int32_t contact = -1;
  double best_score = -1e300;
  for (std::int32_t node : boundary.mesh_node_of_vertex) {
    const nav::Point3 offset = liver.mesh.nodes_m[node] - liver.tumour_centre_m;
    const double score = offset[1] - 4.0 * std::hypot(offset[0], offset[2]);  // anterior, above the tumour
    if (score > best_score) best_score = score, contact = node;
  }
  std::vector<std::int32_t> patch;
  for (std::int32_t node : boundary.mesh_node_of_vertex)
    if (nav::norm(liver.mesh.nodes_m[node] - liver.mesh.nodes_m[contact]) <= radius_m) patch.push_back(node);
  std::vector<nav::PointForce> forces;
  for (std::int32_t node : patch)
    forces.push_back({node, nav::Point3{0.0, -force_n / static_cast<double>(patch.size()), 0.0}});
  return forces;
}

struct CaseFigures {
  double max_displacement_m = 0.0;
  double tumour_displacement_m = 0.0;
};

CaseFigures summarise(const nav::TetMesh& mesh, const std::vector<nav::Point3>& displacement_m) {
  CaseFigures figures;
  for (const nav::Point3& u : displacement_m)
    figures.max_displacement_m = std::max(figures.max_displacement_m, nav::norm(u));
  figures.tumour_displacement_m = nav::norm(tumour_displacement_m(mesh, displacement_m));
  return figures;
}

/// The neo-Hookean equilibrium of `scene` under `loads`, as displacements from rest.
nav::Result<std::vector<nav::Point3>> solve_reference(const nav::TetMesh& mesh, const nav::TissueScene& scene,
                                                      const nav::TissueInputs& loads, int& newton_iterations) {
  auto solved = nav::solve_newton_static(mesh, scene, loads, {});
  if (!solved.ok()) return solved.error();
  newton_iterations = solved.value().newton_iterations;
  std::vector<nav::Point3> displacement_m(mesh.nodes_m.size());
  for (std::size_t n = 0; n < displacement_m.size(); ++n)
    for (int k = 0; k < 3; ++k) displacement_m[n][k] = solved.value().positions_m[3 * n + k] - mesh.nodes_m[n][k];
  return displacement_m;
}

nav::VtuField displacement_field(const std::string& name, const std::vector<nav::Point3>& displacement_m) {
  nav::VtuField field{name, 3, {}};
  for (const nav::Point3& u : displacement_m) field.values.insert(field.values.end(), u.begin(), u.end());
  return field;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse_options(argc, argv, options)) return kExitBadInput;

  auto start = std::chrono::steady_clock::now();
  const nav::EmbeddedLiver liver = nav::make_embedded_liver(options.element_size_m);
  const double mesh_s = seconds_since(start);
  const nav::TetMeshReport report = nav::validate_tet_mesh(liver.mesh);
  std::size_t tumour_tets = 0;
  for (std::int32_t region : liver.mesh.tet_regions)
    tumour_tets += region == static_cast<std::int32_t>(nav::TissueRegion::tumour);
  std::printf("embedded liver: %zu nodes, %zu tetrahedra (%zu in the tumour), %.3f L, element size %.1f mm\n",
              report.nodes, report.tetrahedra, tumour_tets, report.volume_m3 * 1e3, options.element_size_m * 1e3);
  std::printf("  quality: %zu inverted, min radius ratio %.3f, min dihedral %.1f deg; meshed in %.0f ms\n",
              report.inverted, report.min_quality, report.min_dihedral_deg, mesh_s * 1e3);
  std::printf("  tumour centre (%.1f, %.1f, %.1f) mm, radius %.1f mm; %zu attachment nodes\n",
              liver.tumour_centre_m[0] * 1e3, liver.tumour_centre_m[1] * 1e3, liver.tumour_centre_m[2] * 1e3,
              liver.tumour_radius_m * 1e3, liver.attachment_nodes.size());

  // One scene and one set of loads for both solvers: the materials, supports and gravity stated here.
  nav::TissueScene scene;
  scene.default_material = {5000.0, 0.45, 1060.0};  // parenchyma
  scene.region_materials = {{static_cast<std::int32_t>(nav::TissueRegion::tumour), {20'000.0, 0.45, 1060.0}}};
  scene.gravity_m_s2 = {0.0, -9.81, 0.0};  // patient supine: gravity points posteriorly (-y)
  scene.fixed_nodes = liver.attachment_nodes;
  std::vector<nav::PointForce> forces;

  std::vector<nav::VtuField> point_fields;
  std::vector<nav::VtuField> cell_fields;
  for (const bool with_probe : {false, true}) {
    if (with_probe) forces = probe_forces(liver, options.probe_force_n, options.probe_radius_m);
    scene.max_point_forces = std::max(scene.max_point_forces, forces.size());
    nav::TissueInputs loads;
    loads.point_forces = forces;
    const char* name = with_probe ? "gravity + probe" : "gravity";
    start = std::chrono::steady_clock::now();
    int newton_iterations = 0;
    auto reference = solve_reference(liver.mesh, scene, loads, newton_iterations);
    const double reference_s = seconds_since(start);
    start = std::chrono::steady_clock::now();
    auto linear = nav::solve_linear_static(liver.mesh, scene, loads);
    const double linear_s = seconds_since(start);
    if (!reference.ok() || !linear.ok()) {
      std::fprintf(stderr, "navdemo: %s: %s\n", name,
                   (reference.ok() ? linear.error() : reference.error()).describe().c_str());
      return 1;
    }
    if (with_probe) std::printf("probe: %.1f N on %zu surface nodes\n", options.probe_force_n, forces.size());
    const CaseFigures figures = summarise(liver.mesh, reference.value());
    std::printf("%s: neo-Hookean static solve (%lld dofs, %d Newton iterations) in %.0f ms\n", name,
                static_cast<long long>(linear.value().free_dofs), newton_iterations, reference_s * 1e3);
    std::printf("  max displacement %.2f mm, tumour displacement %.2f mm\n", figures.max_displacement_m * 1e3,
                figures.tumour_displacement_m * 1e3);
    // The cheap rung beside it: linear FEM, and what it gets wrong at this displacement.
    const CaseFigures cheap = summarise(liver.mesh, linear.value().displacement_m);
    std::vector<nav::Point3> error_m(reference.value().size());
    double max_error_m = 0.0;
    for (std::size_t n = 0; n < error_m.size(); ++n) {
      error_m[n] = linear.value().displacement_m[n] - reference.value()[n];
      max_error_m = std::max(max_error_m, nav::norm(error_m[n]));
    }
    const double tumour_error_m = nav::norm(tumour_displacement_m(liver.mesh, error_m));
    std::printf(
        "  linear FEM in %.0f ms: max displacement %.2f mm, tumour %.2f mm; its error: %.2f mm at worst, %.2f mm at "
        "the tumour\n",
        linear_s * 1e3, cheap.max_displacement_m * 1e3, cheap.tumour_displacement_m * 1e3, max_error_m * 1e3,
        tumour_error_m * 1e3);

    const std::string suffix = with_probe ? "_gravity_probe" : "_gravity";
    point_fields.push_back(displacement_field("displacement_m" + suffix, reference.value()));
    point_fields.push_back(displacement_field("linear_displacement_m" + suffix, linear.value().displacement_m));
    point_fields.push_back(displacement_field("linear_error_m" + suffix, error_m));
    point_fields.push_back({"linear_von_mises_stress_pa" + suffix, 1, linear.value().nodal_von_mises_stress_pa});
    cell_fields.push_back({"linear_von_mises_stress_pa" + suffix, 1, linear.value().von_mises_stress_pa});
  }

  const nav::Status written = nav::write_vtu(options.out_path, liver.mesh, point_fields, cell_fields);
  if (!written.ok()) {
    std::fprintf(stderr, "navdemo: %s\n", written.error().describe().c_str());
    return 1;
  }
  std::printf("result written to %s (open it in ParaView or 3D Slicer)\n", options.out_path.c_str());
  return 0;
}
