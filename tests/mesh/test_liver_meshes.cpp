// The real liver meshes of ../shared/data/liver (read in place): published counts, no inverted
// element, closed boundary, and the loading time of the 1 MB volume mesh.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "nav/mesh/load_mesh.hpp"
#include "nav/mesh/validation.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;

std::string liver_path(const char* name) { return nav::testing::shared_data_path(std::string("liver/") + name); }

TEST(LiverMeshes, VolumeMeshHasItsPublishedCountsAndNoInvertedElement) {
  const std::string path = liver_path("liverFine.vtu");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto mesh = nav::load_tet_mesh(path, LengthUnit::centimetre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  const auto report = nav::validate_tet_mesh(mesh.value());
  EXPECT_EQ(report.nodes, 4293u);
  EXPECT_EQ(report.tetrahedra, 22019u);
  EXPECT_EQ(report.inverted, 0u);
  EXPECT_EQ(report.out_of_range_indices, 0u);
  EXPECT_EQ(report.unreferenced_nodes, 0u);
  EXPECT_GT(report.min_quality, 0.0);
  // The published mesh has 11 slivers below the 0.05 radius-ratio threshold (worst 0.013).
  EXPECT_EQ(report.degenerate, 11u);
  // A liver of a few centimetres across: some hundreds of cubic centimetres.
  EXPECT_GT(report.volume_m3, 1e-5);
  EXPECT_LT(report.volume_m3, 1e-3);
  std::printf("liverFine.vtu: volume %.6g m3, radius ratio min %.4f mean %.4f, min dihedral %.2f deg, %zu degenerate\n",
              report.volume_m3, report.min_quality, report.mean_quality, report.min_dihedral_deg, report.degenerate);
}

TEST(LiverMeshes, VolumeMeshBoundaryIsClosedAndEnclosesTheMeshVolume) {
  const std::string path = liver_path("liverFine.vtu");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto mesh = nav::load_tet_mesh(path, LengthUnit::centimetre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  const auto boundary = nav::extract_boundary(mesh.value());
  const auto surface = nav::validate_surface(boundary.surface);
  EXPECT_TRUE(surface.closed);
  EXPECT_TRUE(surface.consistently_oriented);
  const double volume_m3 = nav::validate_tet_mesh(mesh.value()).volume_m3;
  EXPECT_NEAR(surface.enclosed_volume_m3, volume_m3, 1e-12 * volume_m3 + 1e-18);
}

TEST(LiverMeshes, SmoothSurfaceIsClosedAndOutward) {
  const std::string path = liver_path("liver-smoothUV.obj");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto surface = nav::load_surface(path, LengthUnit::centimetre);
  ASSERT_TRUE(surface.ok()) << surface.error().describe();
  const auto report = nav::validate_surface(surface.value());
  EXPECT_EQ(report.vertices, 2194u);
  EXPECT_EQ(report.triangles, 4384u);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_GT(report.enclosed_volume_m3, 0.0);
  std::printf("liver-smoothUV.obj: enclosed volume %.6g m3\n", report.enclosed_volume_m3);
}

TEST(LiverMeshes, VolumeMeshLoadsWellUnderOneHundredMilliseconds) {
  const std::string path = liver_path("liverFine.vtu");
  NAV_REQUIRE_SHARED_DATA(path);
  ASSERT_TRUE(nav::load_tet_mesh(path, LengthUnit::centimetre).ok());  // warm the file cache
  double best_ms = 1e9;
  for (int run = 0; run < 5; ++run) {
    const auto start = std::chrono::steady_clock::now();
    const auto mesh = nav::load_tet_mesh(path, LengthUnit::centimetre);
    const auto stop = std::chrono::steady_clock::now();
    ASSERT_TRUE(mesh.ok());
    best_ms = std::min(best_ms, std::chrono::duration<double, std::milli>(stop - start).count());
  }
  std::printf("liverFine.vtu loads in %.2f ms (best of 5)\n", best_ms);
#ifdef NDEBUG
  EXPECT_LT(best_ms, 100.0);
#endif
}

}  // namespace
