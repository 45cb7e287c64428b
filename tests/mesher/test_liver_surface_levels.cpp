// The real liver surface (shared data, centimetres) meshed at about 1k, 5k, 20k and 80k
// elements: no inverted element at any level, and the finest level's volume within 3 % of the
// volume the surface encloses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/obj_reader.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/mesher/surface_domain.hpp"
#include "support/test_data.hpp"

namespace nav {
namespace {

class LiverSurfaceLevels : public ::testing::TestWithParam<double> {
 protected:
  void SetUp() override {
    const std::string path = testing::shared_data_path("liver/liver-smoothUV.obj");
    NAV_REQUIRE_SHARED_DATA(path);
    auto surface = load_obj_surface(path, LengthUnit::centimetre);
    ASSERT_TRUE(surface.ok()) << surface.error().describe();
    surface_volume_m3_ = enclosed_volume_m3(surface.value());
    domain_ = std::make_unique<SurfaceDomain>(surface.value());
  }

  double surface_volume_m3_ = 0.0;
  std::unique_ptr<SurfaceDomain> domain_;
};

TEST_P(LiverSurfaceLevels, MeshesWithoutInversionNearTheTargetCount) {
  const double target_tets = GetParam();
  const double h = element_size_for_tet_count_m(surface_volume_m3_, target_tets);
  const auto made = make_tet_mesh(*domain_, {.element_size_m = h, .fitting = {}});
  ASSERT_TRUE(made.ok()) << made.error().describe();
  const MesherOutput& out = made.value();
  const double volume_error = total_volume_m3(out.mesh) / surface_volume_m3_ - 1.0;
  std::printf(
      "target %6.0f: h %.2f mm, %zu tets, %zu nodes, volume error %+.2f %%, min radius ratio %.3f, "
      "min dihedral %.1f deg, %zu nodes off the surface\n",
      target_tets, h * 1e3, out.mesh.tets.size(), out.mesh.nodes_m.size(), 100.0 * volume_error,
      out.report.quality.min_quality, out.report.quality.min_dihedral_deg, out.report.fitting.unsnapped_nodes.size());
  EXPECT_EQ(out.report.quality.inverted, 0u);
  EXPECT_GT(out.report.quality.min_quality, 0.05);
  EXPECT_NEAR(static_cast<double>(out.mesh.tets.size()) / target_tets, 1.0, 0.2);
  if (target_tets >= 80000.0) {
    EXPECT_LT(std::abs(volume_error), 0.03);
  }
}

INSTANTIATE_TEST_SUITE_P(AboutTetCounts, LiverSurfaceLevels, ::testing::Values(1000.0, 5000.0, 20000.0, 80000.0),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return std::to_string(static_cast<int>(info.param)) + "_tets";
                         });

}  // namespace
}  // namespace nav
