// VTK legacy .vtk: both CELLS layouts, non-tetrahedral cells skipped, unsupported variants refused.
#include <gtest/gtest.h>

#include "nav/mesh/vtk_reader.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;
using Tets = std::vector<std::array<std::int32_t, 4>>;

TEST(VtkReader, ClassicLayoutSkipsVertexAndTriangleCells) {
  const auto mesh = nav::load_vtk_tet_mesh(nav::testing::test_data_path("mesh/cube.vtk"), LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().tets.size(), 6u);
  EXPECT_EQ(mesh.value().tets.front(), (std::array<std::int32_t, 4>{0, 1, 2, 6}));
  EXPECT_TRUE(mesh.value().tet_regions.empty());  // attribute data are not read
}

TEST(VtkReader, Version51OffsetsAndConnectivityLayout) {
  const auto mesh = nav::load_vtk_tet_mesh(nav::testing::test_data_path("mesh/cube_v51.vtk"), LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().tets, (Tets{{0, 1, 3, 4}, {2, 1, 6, 3}, {5, 1, 4, 6}, {7, 3, 6, 4}, {1, 3, 4, 6}}));
}

TEST(VtkReader, BinaryAndOtherDatasetsAreRefusedOnTheirLine) {
  const auto binary = nav::parse_vtk_tet_mesh("# vtk DataFile Version 3.0\nt\nBINARY\n", "b.vtk", LengthUnit::metre);
  ASSERT_FALSE(binary.ok());
  EXPECT_EQ(binary.error().line, 3);
  const auto polydata =
      nav::parse_vtk_tet_mesh("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n", "p.vtk", LengthUnit::metre);
  ASSERT_FALSE(polydata.ok());
  EXPECT_EQ(polydata.error().describe(), "p.vtk:4: DATASET: 'POLYDATA' is not supported (UNSTRUCTURED_GRID is read)");
}

TEST(VtkReader, OutOfRangePointIndexIsLocatedOnItsOwnLine) {
  const std::string text =
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0\n0 1 0 0 0 1\n"
      "CELLS 2 10\n4 0 1 2 3\n4 0 1\n2 4\nCELL_TYPES 2\n10 10\n";
  const auto mesh = nav::parse_vtk_tet_mesh(text, "r.vtk", LengthUnit::metre);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().describe(), "r.vtk:11: CELLS: point index 4 is out of range (4 points)");
}

}  // namespace
