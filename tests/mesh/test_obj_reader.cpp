// The .obj surface loader: record forms, fan triangulation, units, and the real liver surface.
#include <gtest/gtest.h>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/obj_reader.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;

TEST(ObjReader, CubeWithQuadsAndMixedCornerFormsHasUnitVolume) {
  const auto surface = nav::load_obj_surface(nav::testing::test_data_path("mesh/cube.obj"), LengthUnit::metre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  EXPECT_EQ(surface.value().vertices_m.size(), 8u);
  EXPECT_EQ(surface.value().triangles.size(), 12u);
  EXPECT_DOUBLE_EQ(nav::enclosed_volume_m3(surface.value()), 1.0);
}

TEST(ObjReader, CentimetreCoordinatesAreScaledToMetres) {
  const auto surface = nav::load_obj_surface(nav::testing::test_data_path("mesh/cube.obj"), LengthUnit::centimetre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  EXPECT_DOUBLE_EQ(surface.value().vertices_m[6][0], 0.01);
  EXPECT_NEAR(nav::enclosed_volume_m3(surface.value()), 1e-6, 1e-20);
}

TEST(ObjReader, PolygonIsFanTriangulatedFromItsFirstCorner) {
  const auto surface = nav::parse_obj_surface("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 2 0\nv 0 1 0\nf 1 2 3 4 5\n",
                                              "pentagon.obj", LengthUnit::metre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  const std::vector<std::array<std::int32_t, 3>> expected{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}};
  EXPECT_EQ(surface.value().triangles, expected);
}

TEST(ObjReader, NegativeIndicesCountBackFromTheLastVertex) {
  const auto surface = nav::parse_obj_surface("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -1 -3\n",
                                              "negative.obj", LengthUnit::metre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  const std::vector<std::array<std::int32_t, 3>> expected{{0, 1, 2}, {0, 3, 1}};
  EXPECT_EQ(surface.value().triangles, expected);
}

TEST(ObjReader, IndexBeyondTheVerticesDefinedSoFarNamesItsLine) {
  const auto surface = nav::parse_obj_surface("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", "bad.obj", LengthUnit::metre);
  ASSERT_FALSE(surface.ok());
  EXPECT_EQ(surface.error().file, "bad.obj");
  EXPECT_EQ(surface.error().line, 5);
  EXPECT_EQ(surface.error().field, "f");
  EXPECT_NE(surface.error().message.find("out of range"), std::string::npos);
}

TEST(ObjReader, RealLiverSurfaceHasItsPublishedCounts) {
  const std::string path = nav::testing::shared_data_path("liver/liver-smoothUV.obj");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto surface = nav::load_obj_surface(path, LengthUnit::centimetre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  EXPECT_EQ(surface.value().vertices_m.size(), 2194u);
  EXPECT_EQ(surface.value().triangles.size(), 4384u);
  EXPECT_GT(nav::enclosed_volume_m3(surface.value()), 0.0);
}

}  // namespace
