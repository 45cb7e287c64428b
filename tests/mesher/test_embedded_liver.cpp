// The embedded default liver: size, volume, validity, tumour and attachments, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "mesher/test_shapes.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/mesher/surface_proximity.hpp"

namespace nav {
namespace {

class EmbeddedLiverTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { liver_ = new EmbeddedLiver(make_embedded_liver(kEmbeddedLiverElementSizeM)); }
  static void TearDownTestSuite() {
    delete liver_;
    liver_ = nullptr;
  }
  static const EmbeddedLiver& liver() { return *liver_; }

 private:
  static EmbeddedLiver* liver_;
};

EmbeddedLiver* EmbeddedLiverTest::liver_ = nullptr;

/// True if `p` lies in (or on) some element of `mesh`.
bool inside_mesh(const TetMesh& mesh, const Point3& p) {
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto& t = mesh.tets[e];
    const Point3* c[4] = {&mesh.nodes_m[t[0]], &mesh.nodes_m[t[1]], &mesh.nodes_m[t[2]], &mesh.nodes_m[t[3]]};
    bool inside = true;
    for (int k = 0; k < 4 && inside; ++k) {
      const Point3* corners[4] = {c[0], c[1], c[2], c[3]};
      corners[k] = &p;
      inside = signed_tet_volume_m3(*corners[0], *corners[1], *corners[2], *corners[3]) >= 0.0;
    }
    if (inside) return true;
  }
  return false;
}

TEST_F(EmbeddedLiverTest, HasAboutFiveThousandValidElements) {
  const TetMeshReport report = validate_tet_mesh(liver().mesh);
  EXPECT_NEAR(static_cast<double>(report.tetrahedra), 5000.0, 1000.0);
  EXPECT_EQ(report.inverted, 0u);
  EXPECT_EQ(report.unreferenced_nodes, 0u);
  EXPECT_GT(report.min_quality, 0.05);
}

TEST_F(EmbeddedLiverTest, VolumeAndSizeOfAnAdultLiver) {
  const double volume_l = total_volume_m3(liver().mesh) * 1e3;
  EXPECT_GE(volume_l, 1.3);
  EXPECT_LE(volume_l, 1.7);
  // About 20 (left-right) x 15 (anterior-posterior) x 10 (superior-inferior) cm, within 25 %.
  const Bounds3 box = bounds_of(liver().mesh.nodes_m);
  const double expected_m[3] = {0.20, 0.15, 0.10};
  for (int a = 0; a < 3; ++a) EXPECT_NEAR((box.max_m[a] - box.min_m[a]) / expected_m[a], 1.0, 0.25) << "axis " << a;
}

TEST_F(EmbeddedLiverTest, TumourRegionMatchesItsBall) {
  const TetMesh& mesh = liver().mesh;
  ASSERT_EQ(mesh.tet_regions.size(), mesh.tets.size());
  double tumour_m3 = 0.0;
  std::size_t tumour_tets = 0;
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto region = static_cast<TissueRegion>(mesh.tet_regions[e]);
    ASSERT_TRUE(region == TissueRegion::tumour || region == TissueRegion::parenchyma);
    if (region != TissueRegion::tumour) continue;
    ++tumour_tets;
    tumour_m3 += signed_tet_volume_m3(mesh, e);
  }
  EXPECT_GT(tumour_tets, 0u);
  const double r = liver().tumour_radius_m;
  EXPECT_NEAR(r, 0.015, 0.005);
  EXPECT_NEAR(tumour_m3 / (4.0 / 3.0 * std::numbers::pi * r * r * r), 1.0, 0.15);
}

TEST_F(EmbeddedLiverTest, TumourCentreIsDeepInside) {
  const TetMesh& mesh = liver().mesh;
  EXPECT_TRUE(inside_mesh(mesh, liver().tumour_centre_m));
  const TetMeshBoundary boundary = extract_boundary(mesh);
  const Point3 closest = SurfaceProximity(boundary.surface).closest_point(liver().tumour_centre_m);
  EXPECT_GE(norm(closest - liver().tumour_centre_m), 0.02);
}

TEST_F(EmbeddedLiverTest, AttachmentsAreBoundaryNodesOfHilumAndLigaments) {
  const auto& nodes = liver().attachment_nodes;
  ASSERT_FALSE(nodes.empty());
  EXPECT_TRUE(std::is_sorted(nodes.begin(), nodes.end()));
  EXPECT_EQ(std::adjacent_find(nodes.begin(), nodes.end()), nodes.end());
  const auto boundary = extract_boundary(liver().mesh).mesh_node_of_vertex;
  for (const std::int32_t n : nodes) EXPECT_TRUE(std::binary_search(boundary.begin(), boundary.end(), n)) << n;
  // One group each: below the centre (hilum), on top between the lobes (falciform
  // ligament), at the back of the top (coronary ligament).
  const auto count = [&](auto&& where) {
    return std::count_if(nodes.begin(), nodes.end(), [&](std::int32_t n) { return where(liver().mesh.nodes_m[n]); });
  };
  EXPECT_GT(count([](const Point3& p) { return p[2] < -0.02 && std::abs(p[0]) < 0.04; }), 0);
  EXPECT_GT(count([](const Point3& p) { return p[2] > 0.02 && p[1] > 0.0 && std::abs(p[0] - 0.012) < 0.015; }), 0);
  EXPECT_GT(count([](const Point3& p) { return p[2] > 0.0 && p[1] < -0.04; }), 0);
}

TEST_F(EmbeddedLiverTest, IsDeterministic) {
  const EmbeddedLiver again = make_embedded_liver(kEmbeddedLiverElementSizeM);
  EXPECT_TRUE(testing::bitwise_equal(again.mesh, liver().mesh));
  EXPECT_EQ(again.attachment_nodes, liver().attachment_nodes);
}

TEST(EmbeddedLiver, RejectsSizesItCannotMesh) {
  EXPECT_THROW(make_embedded_liver(0.0), std::invalid_argument);
  EXPECT_THROW(make_embedded_liver(1e-5), std::invalid_argument);
}

}  // namespace
}  // namespace nav
