// write_vtu: a file ParaView reads (checked by structure) that the .vtu reader reads back
// bit for bit, with named point and cell arrays; bad fields are refused.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "nav/mesh/text_lines.hpp"
#include "nav/mesh/vtu_reader.hpp"
#include "nav/mesh/vtu_writer.hpp"
#include "support/test_data.hpp"

namespace {

/// Two tetrahedra on awkward coordinates (no short decimal form), with region tags.
nav::TetMesh awkward_mesh() {
  std::mt19937_64 generator(20240611);
  std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
  nav::TetMesh mesh;
  const std::vector<nav::Point3> base{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  for (const auto& p : base)
    mesh.nodes_m.push_back(
        {p[0] / 3.0 + jitter(generator), p[1] / 7.0 + jitter(generator), p[2] * 1e-7 / 3.0 + jitter(generator)});
  mesh.tets = {{0, 1, 2, 3}, {1, 4, 2, 3}};
  mesh.tet_regions = {static_cast<std::int32_t>(nav::TissueRegion::parenchyma),
                      static_cast<std::int32_t>(nav::TissueRegion::tumour)};
  return mesh;
}

std::vector<nav::VtuField> point_fields(std::size_t nodes) {
  nav::VtuField displacement{"displacement_m", 3, {}};
  nav::VtuField stress{"von_mises_stress_pa", 1, {}};
  for (std::size_t n = 0; n < nodes; ++n) {
    displacement.values.insert(displacement.values.end(), {0.1 * n, -1e-300, 1.0 / 3.0});
    stress.values.push_back(1234.5 + static_cast<double>(n));
  }
  return {displacement, stress};
}

TEST(VtuWriter, ReaderReadsBackBitExactCoordinatesConnectivityAndRegions) {
  const nav::TetMesh mesh = awkward_mesh();
  const std::string path = nav::testing::temporary_path("round_trip.vtu");
  const auto status =
      nav::write_vtu(path, mesh, point_fields(mesh.nodes_m.size()), {{"strain_energy_j", 1, {1e-9, 2e-9}}});
  ASSERT_TRUE(status.ok()) << status.error().describe();
  const auto back = nav::load_vtu_tet_mesh(path, nav::LengthUnit::metre);
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_EQ(back.value().nodes_m, mesh.nodes_m);  // operator== on doubles: bit-exact
  EXPECT_EQ(back.value().tets, mesh.tets);
  EXPECT_EQ(back.value().tet_regions, mesh.tet_regions);
  std::remove(path.c_str());
}

TEST(VtuWriter, NamedArraysAreWrittenWithTheirComponentCounts) {
  const nav::TetMesh mesh = awkward_mesh();
  const auto text = nav::format_vtu(mesh, point_fields(mesh.nodes_m.size()), {});
  ASSERT_TRUE(text.ok()) << text.error().describe();
  const std::string& vtu = text.value();
  EXPECT_NE(vtu.find("<DataArray type=\"Float64\" Name=\"displacement_m\" NumberOfComponents=\"3\" format=\"ascii\">"),
            std::string::npos);
  EXPECT_NE(vtu.find("Name=\"von_mises_stress_pa\" NumberOfComponents=\"1\""), std::string::npos);
  EXPECT_NE(vtu.find("<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">"), std::string::npos);
  EXPECT_NE(vtu.find("-1e-300"), std::string::npos);
  EXPECT_NE(vtu.find("0.3333333333333333"), std::string::npos);  // shortest round-trip form
  EXPECT_LT(vtu.find("<PointData>"), vtu.find("<CellData>"));
  EXPECT_LT(vtu.find("<CellData>"), vtu.find("<Points>"));
  EXPECT_LT(vtu.find("<Points>"), vtu.find("<Cells>"));
}

TEST(VtuWriter, EveryValueOfTheWrittenTextParsesBackToTheSameDouble) {
  const nav::TetMesh mesh = awkward_mesh();
  const auto fields = point_fields(mesh.nodes_m.size());
  const auto text = nav::format_vtu(mesh, fields, {});
  ASSERT_TRUE(text.ok());
  const std::string& vtu = text.value();
  const std::size_t start = vtu.find('>', vtu.find("Name=\"displacement_m\"")) + 1;
  nav::TextScanner scanner("written.vtu", std::string_view(vtu).substr(start, vtu.find('<', start) - start));
  for (const double expected : fields[0].values) {
    double value = 0.0;
    ASSERT_TRUE(scanner.read(value, "displacement_m"));
    EXPECT_EQ(value, expected);
  }
  EXPECT_TRUE(scanner.at_end());
}

TEST(VtuWriter, MeshWithoutRegionsWritesNoRegionArray) {
  nav::TetMesh mesh = awkward_mesh();
  mesh.tet_regions.clear();
  const auto text = nav::format_vtu(mesh, {}, {});
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(text.value().find("Name=\"region\""), std::string::npos);
  const auto back = nav::parse_vtu_tet_mesh(text.value(), "written.vtu", nav::LengthUnit::metre);
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_TRUE(back.value().tet_regions.empty());
}

TEST(VtuWriter, FieldOfTheWrongSizeIsRefusedWithItsName) {
  const nav::TetMesh mesh = awkward_mesh();
  const auto status =
      nav::write_vtu(nav::testing::temporary_path("never.vtu"), mesh, {{"displacement_m", 3, {1, 2, 3}}});
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().describe().find("displacement_m"), std::string::npos);
  EXPECT_NE(status.error().describe().find("expected 15"), std::string::npos) << status.error().describe();
}

TEST(VtuWriter, BadNamesNonFiniteValuesAndOutOfRangeIndicesAreRefused) {
  nav::TetMesh mesh = awkward_mesh();
  EXPECT_FALSE(nav::format_vtu(mesh, {{"a\"b", 1, std::vector<double>(5, 0.0)}}, {}).ok());
  EXPECT_FALSE(nav::format_vtu(mesh, {{"p", 1, {0, 0, 0, 0, std::nan("")}}}, {}).ok());
  EXPECT_FALSE(nav::format_vtu(mesh, {}, {{"region", 1, {0, 0}}}).ok());
  mesh.tets[1][2] = 5;
  EXPECT_FALSE(nav::format_vtu(mesh, {}, {}).ok());
}

TEST(VtuWriter, UnwritablePathGivesAnErrorNamingIt) {
  const auto status = nav::write_vtu("/nonexistent-folder/out.vtu", awkward_mesh());
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().file, "/nonexistent-folder/out.vtu");
}

}  // namespace
