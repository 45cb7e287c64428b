// Gmsh .msh 2.2 and 4.1: sparse node tags remapped, non-tetrahedra skipped, region tags kept.
#include <gtest/gtest.h>

#include "nav/mesh/msh_reader.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;
using Tets = std::vector<std::array<std::int32_t, 4>>;

nav::TetMesh load_msh(const char* name) {
  auto mesh = nav::load_msh_tet_mesh(nav::testing::test_data_path(std::string("mesh/") + name), LengthUnit::metre);
  EXPECT_TRUE(mesh.ok()) << mesh.error().describe();
  return mesh.ok() ? std::move(mesh).value() : nav::TetMesh{};
}

TEST(MshReader, Version22RemapsSparseTagsInFileOrderAndKeepsPhysicalTags) {
  const nav::TetMesh mesh = load_msh("cube_v22.msh");
  ASSERT_EQ(mesh.nodes_m.size(), 8u);
  EXPECT_EQ(mesh.nodes_m[2], (nav::Point3{1, 1, 0}));  // tag 17, third in $Nodes
  const Tets expected{{0, 1, 2, 6}, {0, 1, 6, 5}, {0, 3, 6, 2}, {0, 3, 7, 6}, {0, 4, 5, 6}, {0, 4, 6, 7}};
  EXPECT_EQ(mesh.tets, expected);  // the point, line and triangle elements are skipped
  EXPECT_EQ(mesh.tet_regions, (std::vector<std::int32_t>{1, 1, 1, 2, 2, 2}));
}

TEST(MshReader, Version41ReadsNodeBlocksAndTakesTheVolumesPhysicalTag) {
  const nav::TetMesh mesh = load_msh("cube_v41.msh");
  ASSERT_EQ(mesh.nodes_m.size(), 8u);
  EXPECT_EQ(mesh.nodes_m[7], (nav::Point3{0, 1, 1}));
  const Tets expected{{0, 1, 3, 4}, {2, 1, 6, 3}, {5, 1, 4, 6}, {7, 3, 6, 4}, {1, 3, 4, 6}};
  EXPECT_EQ(mesh.tets, expected);
  EXPECT_EQ(mesh.tet_regions, std::vector<std::int32_t>(5, 7));
}

TEST(MshReader, Version41WithoutEntitiesUsesTheEntityTagAndSkipsParametricCoordinates) {
  const std::string text =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$Nodes\n1 4 1 4\n3 5 1 4\n1\n2\n3\n4\n0 0 0 0.1 0.2 0.3\n1 0 0 0 0 0\n0 1 0 0 0 0\n0 0 1 0 0 0\n$EndNodes\n"
      "$Elements\n1 1 1 1\n3 5 4 1\n1 1 2 3 4\n$EndElements\n";
  const auto mesh = nav::parse_msh_tet_mesh(text, "inline.msh", LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().tets, (Tets{{0, 1, 2, 3}}));
  EXPECT_EQ(mesh.value().tet_regions, (std::vector<std::int32_t>{5}));
}

TEST(MshReader, Version2ElementsWithoutTagsGiveNoRegions) {
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
      "$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n";
  const auto mesh = nav::parse_msh_tet_mesh(text, "inline.msh", LengthUnit::millimetre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_TRUE(mesh.value().tet_regions.empty());
  EXPECT_EQ(mesh.value().nodes_m[1], (nav::Point3{0.001, 0, 0}));
}

TEST(MshReader, UnknownSectionsAreSkippedToTheirEndMarker) {
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\nanything $Nodes here\n$EndComments\n"
      "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 3 3 1 2 3 4\n$EndElements\n"
      "$NodeData\n1\n\"u\"\n$EndNodeData\n";
  const auto mesh = nav::parse_msh_tet_mesh(text, "inline.msh", LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_EQ(mesh.value().tet_regions, (std::vector<std::int32_t>{3}));
}

TEST(MshReader, ElementReferringToAnUnknownNodeTagNamesLineAndTag) {
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
      "$Elements\n1\n1 4 0 1 2 3 7\n$EndElements\n";
  const auto mesh = nav::parse_msh_tet_mesh(text, "inline.msh", LengthUnit::metre);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().describe(), "inline.msh:13: $Elements: node tag 7 is not in $Nodes");
}

}  // namespace
