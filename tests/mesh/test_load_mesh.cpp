// Every tetrahedral format read through load_tet_mesh gives the same unit cube; units scale.
#include <gtest/gtest.h>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;

class CubeFile : public ::testing::TestWithParam<const char*> {};

TEST_P(CubeFile, LoadsAsTheUnitCubeWithEveryElementPositive) {
  const auto mesh =
      nav::load_tet_mesh(nav::testing::test_data_path(std::string("mesh/") + GetParam()), LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().nodes_m.size(), 8u);
  EXPECT_DOUBLE_EQ(nav::total_volume_m3(mesh.value()), 1.0);
  for (std::size_t e = 0; e < mesh.value().tets.size(); ++e) EXPECT_GT(nav::signed_tet_volume_m3(mesh.value(), e), 0.0);
  const nav::Bounds3 bounds = nav::bounds_of(mesh.value().nodes_m);
  EXPECT_EQ(bounds.min_m, (nav::Point3{0.0, 0.0, 0.0}));
  EXPECT_EQ(bounds.max_m, (nav::Point3{1.0, 1.0, 1.0}));
}

TEST_P(CubeFile, MillimetreAndCentimetreCoordinatesAreScaledToMetres) {
  const std::string path = nav::testing::test_data_path(std::string("mesh/") + GetParam());
  const auto in_mm = nav::load_tet_mesh(path, LengthUnit::millimetre);
  const auto in_cm = nav::load_tet_mesh(path, LengthUnit::centimetre);
  ASSERT_TRUE(in_mm.ok() && in_cm.ok());
  EXPECT_NEAR(nav::total_volume_m3(in_mm.value()), 1e-9, 1e-24);
  EXPECT_NEAR(nav::total_volume_m3(in_cm.value()), 1e-6, 1e-21);
  EXPECT_EQ(nav::bounds_of(in_cm.value().nodes_m).max_m, (nav::Point3{0.01, 0.01, 0.01}));
}

INSTANTIATE_TEST_SUITE_P(AllFormats, CubeFile,
                         ::testing::Values("cube_v22.msh", "cube_v41.msh", "cube.vtk", "cube_v51.vtk", "cube.vtu"));

TEST(LoadMesh, ExtensionIsMatchedWithoutRegardToCase) {
  const auto mesh = nav::load_tet_mesh("/nonexistent/CUBE.VTU", LengthUnit::metre);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().message.find("no such file"), std::string::npos) << mesh.error().describe();
}

TEST(LoadMesh, UnknownExtensionIsRefusedWithThePath) {
  const auto mesh = nav::load_tet_mesh("liver.stl", LengthUnit::metre);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().file, "liver.stl");
  EXPECT_NE(mesh.error().message.find(".stl"), std::string::npos);
  EXPECT_FALSE(nav::load_surface("liver.ply", LengthUnit::metre).ok());
}

TEST(LoadMesh, SurfaceOfTheCubeEnclosesTheSameVolumeAsItsTetrahedra) {
  const auto surface = nav::load_surface(nav::testing::test_data_path("mesh/cube.obj"), LengthUnit::millimetre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  EXPECT_NEAR(nav::enclosed_volume_m3(surface.value()), 1e-9, 1e-24);
}

}  // namespace
