// VTK XML .vtu: ascii arrays, region cell data, skipped arrays and cells, refused variants.
#include <gtest/gtest.h>

#include "nav/mesh/vtu_reader.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;

std::string vtu(const std::string& points_attributes, const std::string& extra_cells = "") {
  return "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
         "<Points>\n<DataArray " +
         points_attributes +
         ">\n0 0 0 1 0 0 0 1 0 0 0 1\n</DataArray>\n</Points>\n"
         "<Cells>\n<DataArray Name='connectivity' format='ascii'>0 1 2 3</DataArray>\n" +
         extra_cells +
         "<DataArray Name=\"offsets\" format=\"ascii\">4</DataArray>\n"
         "<DataArray Name=\"types\" format=\"ascii\">10</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n"
         "</VTKFile>\n";
}

TEST(VtuReader, CubeKeepsTetrahedraAndTheirRegionsAndSkipsTheTriangle) {
  const auto mesh = nav::load_vtu_tet_mesh(nav::testing::test_data_path("mesh/cube.vtu"), LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().tets.size(), 5u);
  EXPECT_EQ(mesh.value().tet_regions, (std::vector<std::int32_t>{1, 1, 1, 1, 2}));
}

TEST(VtuReader, SingleQuotedAttributesAndArraysOnOneLineAreRead) {
  const auto mesh =
      nav::parse_vtu_tet_mesh(vtu("type='Float64' NumberOfComponents='3' format='ascii'"), "q.vtu", LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().tets.size(), 1u);
}

TEST(VtuReader, BinaryDataArrayIsRefusedNamingFileAndLine) {
  const auto mesh = nav::parse_vtu_tet_mesh(vtu("type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\""), "b.vtu",
                                            LengthUnit::metre);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().describe(), "b.vtu:5: Points: format=\"binary\" DataArrays are not supported (only ascii)");
}

TEST(VtuReader, PointsWithTwoComponentsAreRefused) {
  const auto mesh =
      nav::parse_vtu_tet_mesh(vtu("NumberOfComponents=\"2\" format=\"ascii\""), "c.vtu", LengthUnit::metre);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().line, 5);
}

TEST(VtuReader, GarbledValueIsLocatedInsideItsArray) {
  std::string text = vtu("NumberOfComponents=\"3\" format=\"ascii\"");
  text.replace(text.find("0 0 1\n"), 5, "0 0 x");
  const auto mesh = nav::parse_vtu_tet_mesh(text, "g.vtu", LengthUnit::metre);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().describe(), "g.vtu:6: Points: 'x' is not a finite number");
}

TEST(VtuReader, RealLiverMeshLoads) {
  const std::string path = nav::testing::shared_data_path("liver/liverFine.vtu");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto mesh = nav::load_vtu_tet_mesh(path, LengthUnit::centimetre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().nodes_m.size(), 4293u);
  EXPECT_EQ(mesh.value().tets.size(), 22019u);
  EXPECT_NEAR(mesh.value().nodes_m[0][0], -2.43563e-2, 1e-15);  // first point of the file, cm -> m
}

}  // namespace
