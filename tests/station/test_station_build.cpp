// Building a scene: only what it declares is built (and listed in the footprint), errors of
// the builders name the scene file, the section's line and key, the reduced rung loads its
// artifact, and `navstation --scene FILE --check` runs on the example scene.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "nav/mesher/embedded_liver.hpp"
#include "nav/mesher/liver_shape.hpp"
#include "nav/reduced/reduced_artifact.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/station/station_build.hpp"
#include "nav/station/station_loop.hpp"
#include "nav/station/tumour_observer.hpp"
#include "scene_build.hpp"
#include "scene_text.hpp"
#include "support/run_command.hpp"

namespace nav::station {
namespace {

using testing::build_text;
using testing::demo_text;
using testing::edited;
using testing::example_scene_path;
using testing::line_of;

bool lists(const MemoryFootprint& footprint, const std::string& model) {
  for (const FootprintLine& line : footprint.lines)
    if (line.model == model) return true;
  return false;
}

TEST(StationBuild, DemoBuildsItsLiverAndNeedleAndNothingElse) {
  const auto built = build_text(demo_text());
  ASSERT_TRUE(built.ok()) << built.error().describe();
  const StationModels& m = built.value().models;
  const MemoryFootprint& f = built.value().footprint;
  EXPECT_TRUE(m.liver.full.has_value());
  EXPECT_FALSE(m.liver.reduced.has_value());
  ASSERT_TRUE(m.needle.has_value());
  EXPECT_EQ(m.needle->layer_count(), 2);
  // Its layers are the liver's capsule and its tumour's boundary, taken from the mesh.
  ASSERT_EQ(m.needle->surface_bvhs.size(), 2u);
  EXPECT_EQ(m.needle->scene.layers[0].surface, 0);
  EXPECT_EQ(m.needle->scene.layers[1].surface, 1);
  EXPECT_GT(m.needle->scene.surfaces[0].triangles.size(), 10 * m.needle->scene.surfaces[1].triangles.size());
  EXPECT_FALSE(m.ligaments.has_value());
  EXPECT_TRUE(lists(f, "liver"));
  EXPECT_TRUE(lists(f, "needle"));
  EXPECT_FALSE(lists(f, "ligaments"));
  // The generated liver's own tumour, its nodes and the data arenas as the models report them.
  EXPECT_EQ(m.liver.tumour_m, LiverLandmarks{}.tumour_centre_m);
  EXPECT_EQ(m.liver.full->node_count(), static_cast<std::int64_t>(m.liver.mesh.nodes_m.size()));
  EXPECT_EQ(f.model_bytes("needle"), f.lines[3].bytes + f.lines[4].bytes + f.lines[5].bytes + f.lines[6].bytes);
  EXPECT_GE(f.lines[2].bytes, static_cast<std::int64_t>(m.liver.full_data->arena.used_bytes()));
  EXPECT_EQ(f.total_bytes(), f.model_bytes("liver") + f.model_bytes("needle"));
  const std::string table = format_footprint(f);
  EXPECT_NE(table.find("needle"), std::string::npos);
  EXPECT_NE(table.find(std::to_string(f.total_bytes())), std::string::npos);
}

TEST(StationBuild, AbsentSectionsBuildNothingAndCostNothing) {
  const auto with_needle = build_text(demo_text());
  const std::string text = demo_text();
  const std::string without = text.substr(0, text.find("needle:\n")) + text.substr(text.find("devices:\n"));
  const auto no_needle = build_text(without);
  ASSERT_TRUE(with_needle.ok() && no_needle.ok()) << (no_needle.ok() ? "" : no_needle.error().describe());
  EXPECT_FALSE(no_needle.value().models.needle.has_value());
  EXPECT_FALSE(no_needle.value().models.needle_data.has_value());
  EXPECT_FALSE(lists(no_needle.value().footprint, "needle"));
  EXPECT_EQ(no_needle.value().footprint.total_bytes(),
            with_needle.value().footprint.total_bytes() - with_needle.value().footprint.model_bytes("needle"));
}

TEST(StationBuild, DeclaredLigamentsAreBuiltAndAttachedToTheLiver) {
  const std::string ligaments =
      "ligaments:\n"
      "  material: {youngs_modulus_pa: 100000, poisson_ratio: 0.45, density_kg_m3: 1100}\n"
      "  blocks:\n"
      "    - {footprint_centre_m: [-0.045, 0.0], embed_m: 0.006}\n"
      "    - {footprint_centre_m: [0.035, 0.015], embed_m: 0.006}\n"
      "devices:\n";
  const auto built = build_text(edited(demo_text(), "devices:\n", ligaments));
  ASSERT_TRUE(built.ok()) << built.error().describe();
  const StationModels& m = built.value().models;
  ASSERT_TRUE(m.ligaments.has_value());
  EXPECT_EQ(m.ligaments->grids.size(), 2u);
  EXPECT_TRUE(lists(built.value().footprint, "ligaments"));
  // The attachment's nodes carry the stabilising springs in the liver's scene.
  EXPECT_EQ(m.liver.scene.spring_nodes.size(), m.ligaments->attachment.nodes.size());
  EXPECT_GT(m.liver.scene.spring_stiffness_n_m, 0.0);
}

TEST(StationBuild, TheSceneNetworkIsCheckedBeforeAnyModelIsBuilt) {
  // Loopback with a peer elsewhere: accepted (a peer is only an address to send discovery to).
  const std::string peered = demo_text() + "network:\n  local_address: 127.0.0.1\n  peers: [10.9.8.7, 10.9.8.8]\n";
  const auto built = build_text(peered);
  ASSERT_TRUE(built.ok()) << built.error().describe();
  EXPECT_EQ(built.value().models.scene.network.peers, (std::vector<std::string>{"10.9.8.7", "10.9.8.8"}));
  // An address this host does not hold, a multicast peer, a peer that is no address: refused
  // with the scene's file, the section's line and the key.
  const std::pair<std::string, std::string> refused[] = {
      {"network:\n  local_address: 10.255.255.254\n", "network.local_address"},
      {"network:\n  peers: [239.1.2.3]\n", "network.peers"},
      {"network:\n  peers: [station-b]\n", "network.peers"},
  };
  for (const auto& [section, field] : refused) {
    const std::string text = demo_text() + section;
    const auto failed = build_text(text);
    ASSERT_FALSE(failed.ok()) << section;
    EXPECT_EQ(failed.error().file, example_scene_path("demo.yaml"));
    EXPECT_EQ(failed.error().field, field) << failed.error().describe();
    EXPECT_EQ(failed.error().line, line_of(text, "network:") + 1);  // the section's first key
  }
  // Peers must be a list of addresses.
  const auto not_a_list = parse_scene(demo_text() + "network:\n  peers: {a: 1}\n", example_scene_path("demo.yaml"));
  ASSERT_FALSE(not_a_list.ok());
  EXPECT_NE(not_a_list.error().message.find("a list of the other hosts' IPv4 addresses"), std::string::npos)
      << not_a_list.error().describe();
}

TEST(StationBuild, TheProbeCalibrationIsTheUrdfsImageJoint) {
  auto scene = parse_scene(demo_text(), example_scene_path("demo.yaml"));
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  auto imaging = scene_probe_imaging(scene.value());
  ASSERT_TRUE(imaging.ok()) << imaging.error().describe();
  // The demo's probe: the image's x along the marker's y, its depth (y) along the marker's -z,
  // the marker at the centre of the top edge of 256 pixels of 0.3 mm.
  const Eigen::Isometry3d& probe_from_image = imaging.value().probe_from_image;
  EXPECT_LT((probe_from_image.linear().col(0) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((probe_from_image.linear().col(1) + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_LT((probe_from_image * Eigen::Vector3d(0.5 * 255 * 0.0003, 0.0, 0.0)).norm(), 1e-12);
  // A URDF without the image's joint: the error names the scene and frames.urdf.
  const std::string urdf = testing::temporary_path("no_image.urdf");
  std::ofstream(urdf) << "<robot name=\"r\"><link name=\"tracker\"/><link name=\"probe_marker\"/>"
                         "<joint name=\"tracker_to_probe_marker\" type=\"floating\"><parent link=\"tracker\"/>"
                         "<child link=\"probe_marker\"/></joint></robot>\n";
  scene.value().frames.urdf_path = urdf;
  auto missing = scene_probe_imaging(scene.value());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().field, "frames.urdf");
  EXPECT_EQ(missing.error().file, example_scene_path("demo.yaml"));
  EXPECT_NE(missing.error().message.find("image_plane"), std::string::npos) << missing.error().describe();
}

/// The station URDF with its needle tip joint's origin `xyz`, in a file of its own.
std::string urdf_with_tip(const std::string& xyz, const std::string& name) {
  const std::string path = testing::temporary_path(name);
  const std::string text = testing::file_text(example_scene_path("../../../calibration/urdf/station.urdf"));
  const std::string joint = "<child link=\"needle_tip\"/>\n    <origin xyz=\"0 0 -0.15\"";
  std::ofstream(path) << edited(text, joint, "<child link=\"needle_tip\"/>\n    <origin xyz=\"" + xyz + "\"");
  return path;
}

TEST(StationBuild, TheNeedleIsWhereTheUrdfCalibratesIt) {
  auto scene = parse_scene(demo_text(), example_scene_path("demo.yaml"));
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  // The demo's needle: 0.15 m along the marker's -z, the base at the marker, as the simulated one.
  const auto demo = scene_needle_calibration(scene.value());
  ASSERT_TRUE(demo.ok()) << demo.error().describe();
  EXPECT_LT((demo.value().tip_in_marker_m - Eigen::Vector3d(0.0, 0.0, -0.15)).norm(), 1e-12);
  EXPECT_LT(demo.value().marker_from_base.rotation.angularDistance(needle_marker_from_base().rotation), 1e-12);
  EXPECT_LT(demo.value().marker_from_base.position_m.norm(), 1e-12);
  // A needle calibrated along the marker's x: the base frame's +x follows it.
  scene.value().frames.urdf_path = urdf_with_tip("0.15 0 0", "needle_along_x.urdf");
  const auto along_x = scene_needle_calibration(scene.value());
  ASSERT_TRUE(along_x.ok()) << along_x.error().describe();
  EXPECT_LT((along_x.value().marker_from_base.rotation * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX()).norm(),
            1e-12);
  EXPECT_LT((along_x.value().tip_in_marker_m - Eigen::Vector3d(0.15, 0.0, 0.0)).norm(), 1e-12);
  // A tip 1 cm beyond the scene's needle length: refused at needle.length_m, with both lengths.
  scene.value().frames.urdf_path = urdf_with_tip("0 0 -0.16", "needle_longer.urdf");
  const auto longer = scene_needle_calibration(scene.value());
  ASSERT_FALSE(longer.ok());
  EXPECT_EQ(longer.error().field, "needle.length_m");
  EXPECT_EQ(longer.error().line, line_of(demo_text(), "  length_m: 0.15"));  // the needle section's first key
  EXPECT_NE(longer.error().message.find("160.0 mm"), std::string::npos) << longer.error().describe();
  EXPECT_NE(longer.error().message.find("150.0 mm"), std::string::npos) << longer.error().describe();
}

TEST(StationBuild, BuilderErrorsNameTheSceneSectionAndLine) {
  const std::string bad_urdf =
      edited(demo_text(), "  urdf: ../../../calibration/urdf/station.urdf", "  urdf: missing.urdf");
  const auto frames = build_text(bad_urdf);
  ASSERT_FALSE(frames.ok());
  EXPECT_EQ(frames.error().file, example_scene_path("demo.yaml"));
  EXPECT_EQ(frames.error().field, "frames.urdf");
  EXPECT_EQ(frames.error().line, line_of(bad_urdf, "  urdf:"));
  const std::string outside = edited(demo_text(), "  # tumour_m:", "  tumour_m: [0.5, 0.5, 0.5]\n  #");
  const auto tumour = build_text(outside);
  ASSERT_FALSE(tumour.ok());
  EXPECT_EQ(tumour.error().field, "liver.tumour_m");
  EXPECT_EQ(tumour.error().line, line_of(outside, "  mesh: generated"));
  EXPECT_NE(tumour.error().message.find("outside the liver"), std::string::npos);
  const std::string no_mesh = edited(demo_text(), "  mesh: generated ",
                                     "  tumour_m: [0, 0, 0]\n  mesh: {source: file, path: none.vtu, unit: cm}");
  const auto mesh = build_text(no_mesh);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().field, "liver.mesh");
  EXPECT_NE(mesh.error().message.find("none.vtu"), std::string::npos) << mesh.error().describe();
  const std::string no_region =
      edited(demo_text(), "{surface: tumour, puncture_force_n: 2.0}", "{region: 7, puncture_force_n: 2.0}");
  const auto region = build_text(no_region);
  ASSERT_FALSE(region.ok());
  EXPECT_EQ(region.error().field, "needle.layers[1]");
  EXPECT_EQ(region.error().line, line_of(no_region, "    - {region: 7"));
  EXPECT_NE(region.error().message.find("region 7"), std::string::npos) << region.error().describe();
}

/// A reduced basis of the generated liver at `element_size_m` (4 linear modes of the scene
/// navtool reduce trains on), saved at `path`.
void save_generated_liver_basis(double element_size_m, const std::string& path) {
  const EmbeddedLiver liver = make_embedded_liver(element_size_m);
  const TissueScene scene = liver_reduction_scene(liver.mesh);
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.force_kind = ReducedForceKind::linear;
  options.basis_size = 4;
  const auto basis = make_modal_basis(liver.mesh, scene, reduction_solver_options(options.force_kind), options);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  ASSERT_TRUE(save_reduced_basis(path, basis.value()).ok());
}

TEST(StationBuild, ReducedRungLoadsItsArtifactAndRefusesOneOfAnotherMesh) {
  const std::string artifact = testing::temporary_path("station_generated_liver.navrb");
  save_generated_liver_basis(0.02, artifact);
  const std::string text =
      demo_text().substr(0, demo_text().find("liver:\n") + 7) + "  mesh: {source: generated, element_size_m: 0.02}\n" +
      "  model: {rung: reduced, artifact: " + artifact + "}\n" + demo_text().substr(demo_text().find("\nneedle:") + 1);
  const auto built = build_text(text);
  ASSERT_TRUE(built.ok()) << built.error().describe();
  const LiverModels& liver = built.value().models.liver;
  ASSERT_TRUE(liver.reduced.has_value());
  EXPECT_FALSE(liver.full.has_value());
  EXPECT_EQ(liver.reduced->basis_size(), 4);
  EXPECT_EQ(built.value().footprint.lines[1].part, "reduced tables");
  EXPECT_EQ(built.value().footprint.lines[1].bytes, liver.reduced->memory_bytes());
  const std::string other_mesh = edited(text, "element_size_m: 0.02", "element_size_m: 0.018");
  const auto refused = build_text(other_mesh);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "liver.model.artifact");
  EXPECT_NE(refused.error().message.find("another mesh"), std::string::npos) << refused.error().describe();
}

TEST(StationBuild, NavstationCheckPrintsTheFootprintAndTheRealtimeSetup) {
  const std::string command =
      testing::executable_path("navstation") + " --scene " + example_scene_path("demo.yaml") + " --check 2>&1";
  const auto run = testing::run_command(command);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* expected :
       {"station 'demo'", "memory footprint", "needle", "total", "pin to core", "lock memory", "SCHED_FIFO"})
    EXPECT_NE(run.output.find(expected), std::string::npos) << expected << "\n" << run.output;
  const std::string bad = testing::temporary_path("station_bad_scene.yaml");
  {
    std::ofstream file(bad);
    file << edited(demo_text(), "rung: full", "rung: medium");
  }
  const auto failed =
      testing::run_command(testing::executable_path("navstation") + " --scene " + bad + " --check 2>&1");
  EXPECT_EQ(failed.exit_code, 1);
  EXPECT_NE(failed.output.find(bad + ":" + std::to_string(line_of(demo_text(), "rung: full")) + ": liver.model.rung"),
            std::string::npos)
      << failed.output;
  EXPECT_EQ(testing::run_command(testing::executable_path("navstation") + " --check 2>&1").exit_code, 2);
}

}  // namespace
}  // namespace nav::station
