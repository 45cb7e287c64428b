// Files written by the real tools (Gmsh 4.8: .msh 2.2, .msh 4.1, legacy .vtk; VTK 9.1's XML
// writer: ascii .vtu with a compressor attribute and InformationKey elements) from
// gmsh_ball.geo: all four load as the same mesh, with the physical regions of the .msh files.
#include <gtest/gtest.h>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/mesh/validation.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;

const char* const kBallFiles[] = {"gmsh_ball_v22.msh", "gmsh_ball_v41.msh", "gmsh_ball.vtk", "gmsh_ball.vtu"};

nav::TetMesh load_ball(const std::string& name) {
  auto mesh = nav::load_tet_mesh(nav::testing::test_data_path("mesh/" + name), LengthUnit::millimetre);
  EXPECT_TRUE(mesh.ok()) << mesh.error().describe();
  return mesh.ok() ? std::move(mesh).value() : nav::TetMesh{};
}

TEST(RealWriterFiles, AllFormatsGiveTheSameValidMesh) {
  const nav::TetMesh reference = load_ball(kBallFiles[0]);
  ASSERT_EQ(reference.nodes_m.size(), 247u);
  ASSERT_EQ(reference.tets.size(), 940u);
  for (const char* name : kBallFiles) {
    const nav::TetMesh mesh = load_ball(name);
    ASSERT_EQ(mesh.nodes_m.size(), reference.nodes_m.size()) << name;
    EXPECT_EQ(mesh.tets, reference.tets) << name;
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
      for (int k = 0; k < 3; ++k) ASSERT_NEAR(mesh.nodes_m[n][k], reference.nodes_m[n][k], 1e-15) << name;
    }
    const auto report = nav::validate_tet_mesh(mesh);
    EXPECT_TRUE(report.valid()) << name;
    EXPECT_TRUE(nav::validate_surface(nav::extract_boundary(mesh).surface).closed) << name;
  }
}

TEST(RealWriterFiles, MshPhysicalVolumesBecomeRegions) {
  for (const char* name : {kBallFiles[0], kBallFiles[1]}) {
    const nav::TetMesh mesh = load_ball(name);
    ASSERT_EQ(mesh.tet_regions.size(), mesh.tets.size()) << name;
    double tumour_m3 = 0.0;
    for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
      ASSERT_TRUE(mesh.tet_regions[e] == 1 || mesh.tet_regions[e] == 2) << name;
      if (mesh.tet_regions[e] == 2) tumour_m3 += nav::signed_tet_volume_m3(mesh, e);
    }
    EXPECT_NEAR(tumour_m3, 216e-9, 1e-20) << name;  // the 6 mm box
  }
}

}  // namespace
