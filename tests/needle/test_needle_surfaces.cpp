// The needle against surfaces taken from the mesh (the embedded liver's capsule, its
// boundary, and its tumour, the boundary of the tumour's elements), on the reduced and on the
// full-order liver. Checked against independent geometry written here (winding numbers, ray
// and triangle intersections, point-to-plane and point-to-segment distances):
// the surfaces are closed and enclose their elements' volume; the hierarchy's nearest point
// and side equal the brute force's on a deformed liver; a needle aimed at the tumour punctures
// the capsule, then the tumour, each within one needle element of where its line meets that
// surface on the deformed mesh; a needle 3 mm beside the tumour passes it untouched (where
// the tumour's tangent plane, the layer the surfaces replace, is punctured); an oblique entry
// touches the capsule where its line meets it; ticks allocate nothing and repeat bitwise.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/needle/needle_step.hpp"
#include "nav/needle/needle_tissue_rows.hpp"
#include "nav/needle/reduced_coupling.hpp"
#include "nav/needle/tissue_coupling.hpp"
#include "nav/needle/tissue_surface.hpp"
#include "nav/reduced/reduction.hpp"
#include "needle_coupling_support.hpp"
#include "needle_test_support.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

constexpr int kTissueEvery = 10;          // the liver steps once every 10 needle ticks
constexpr double kStartOutsideM = 0.005;  // the tip starts this far before the capsule
constexpr double kBesideM = 0.003;

Eigen::Vector3d vec(const Point3& p) { return {p[0], p[1], p[2]}; }

Eigen::Vector3d position_m(const std::vector<double>& rest_m, std::span<const double> u, std::int32_t node) {
  const auto at = 3 * static_cast<std::size_t>(node);
  Eigen::Vector3d p(rest_m[at], rest_m[at + 1], rest_m[at + 2]);
  if (!u.empty()) p += Eigen::Vector3d(u[at], u[at + 1], u[at + 2]);
  return p;
}

/// The embedded liver, held at its attachments, with its two surfaces; built once.
struct Liver {
  EmbeddedLiver liver = make_embedded_liver(kEmbeddedLiverElementSizeM);
  TissueSurface capsule = mesh_boundary_surface(liver.mesh);
  TissueSurface tumour = region_boundary_surface(liver.mesh, static_cast<std::int32_t>(TissueRegion::tumour)).value();
  std::vector<double> rest_m;
  TissueScene scene;
  Liver() {
    for (const Point3& p : liver.mesh.nodes_m) rest_m.insert(rest_m.end(), p.begin(), p.end());
    scene.default_material = {2.0e4, 0.45, 1060.0};
    scene.gravity_m_s2 = {0.0, 0.0, 0.0};
    scene.fixed_nodes = liver.attachment_nodes;
    scene.max_point_forces = 32;
  }
};

const Liver& the_liver() {
  static const Liver liver;
  return liver;
}

// --- Independent geometry ----------------------------------------------------------------

/// The generalised winding number of a closed triangle surface at x (1 inside, 0 outside):
/// the solid angles of its triangles (Van Oosterom and Strackee) over 4 pi.
double winding_number(const TissueSurface& s, const std::vector<double>& rest_m, std::span<const double> u,
                      const Eigen::Vector3d& x) {
  double sum = 0.0;
  for (const auto& t : s.triangles) {
    const Eigen::Vector3d a = position_m(rest_m, u, t[0]) - x, b = position_m(rest_m, u, t[1]) - x,
                          c = position_m(rest_m, u, t[2]) - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    sum += 2.0 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return sum / (4.0 * std::numbers::pi);
}

double segment_distance_m(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (x - (a + t * (b - a))).norm();
}

/// The distance from x to a triangle: to its plane where x projects inside it (barycentric
/// signs), else to the nearest of its three edges.
double triangle_distance_m(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d p = x - n.dot(x - a) * n;
  const bool inside =
      n.dot((b - a).cross(p - a)) >= 0.0 && n.dot((c - b).cross(p - b)) >= 0.0 && n.dot((a - c).cross(p - c)) >= 0.0;
  if (inside) return std::abs(n.dot(x - a));
  return std::min({segment_distance_m(x, a, b), segment_distance_m(x, b, c), segment_distance_m(x, c, a)});
}

double surface_distance_m(const TissueSurface& s, const std::vector<double>& rest_m, std::span<const double> u,
                          const Eigen::Vector3d& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : s.triangles)
    best = std::min(best, triangle_distance_m(x, position_m(rest_m, u, t[0]), position_m(rest_m, u, t[1]),
                                              position_m(rest_m, u, t[2])));
  return best;
}

/// The first crossing of the ray origin + t d (t > 0) with the surface (Moeller and Trumbore).
std::optional<Eigen::Vector3d> first_crossing(const TissueSurface& s, const std::vector<double>& rest_m,
                                              std::span<const double> u, const Eigen::Vector3d& origin,
                                              const Eigen::Vector3d& d) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : s.triangles) {
    const Eigen::Vector3d a = position_m(rest_m, u, t[0]), e1 = position_m(rest_m, u, t[1]) - a,
                          e2 = position_m(rest_m, u, t[2]) - a;
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-18) continue;
    const Eigen::Vector3d s0 = origin - a;
    const double v = s0.dot(p) / det;
    const Eigen::Vector3d q = s0.cross(e1);
    const double w = d.dot(q) / det, along = e2.dot(q) / det;
    if (v >= 0.0 && w >= 0.0 && v + w <= 1.0 && along > 0.0) best = std::min(best, along);
  }
  if (!std::isfinite(best)) return std::nullopt;
  return origin + best * d;
}

// --- Insertions ---------------------------------------------------------------------------

/// The needle's scene: the capsule (f_p 0.5 N) and the tumour (1 N) as surfaces, or, for the
/// contrast, the tumour as its tangent plane at `tumour_plane` (point, outward normal).
NeedleTissueScene liver_layers(const Eigen::Vector3d& probe_m,
                               std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> tumour_plane = {}) {
  const Liver& l = the_liver();
  NeedleTissueScene scene;
  scene.surfaces = {l.capsule, l.tumour};
  TissueLayer capsule;
  capsule.surface = 0;
  capsule.surface_point_m = {probe_m.x(), probe_m.y(), probe_m.z()};
  capsule.puncture_force_n = 0.5;
  capsule.cutting_force_n = 0.1;
  capsule.friction_per_length_n_m = 2.0;
  TissueLayer tumour = capsule;
  tumour.puncture_force_n = 1.0;
  tumour.cutting_force_n = 0.3;
  tumour.surface = 1;
  if (tumour_plane) {
    tumour.surface = -1;
    tumour.surface_point_m = {tumour_plane->first.x(), tumour_plane->first.y(), tumour_plane->first.z()};
    tumour.outward_normal = {tumour_plane->second.x(), tumour_plane->second.y(), tumour_plane->second.z()};
  }
  scene.layers = {capsule, tumour};
  scene.path_spacing_m = 0.005;
  return scene;
}

/// Each layer's first touch and puncture along an insertion: the tick, the tip then and the
/// liver's displacements then (puncture).
struct LayerEvents {
  int touched_tick = -1, punctured_tick = -1;
  Eigen::Vector3d touched_tip_m, punctured_tip_m, punctured_base_m, punctured_direction;
  std::vector<double> punctured_displacements_m;
  TissuePoint first_contact;
  double closest_m = std::numeric_limits<double>::infinity();  ///< the tip's closest approach from outside
};

/// The straight needle's base pose for its tip at `tip_m`, pointing along `d`.
NeedlePose pose_for_tip(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& d) {
  const Eigen::Vector3d base = tip_m - NeedleParameters{}.length_m * d;
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), d);
  return {{base.x(), base.y(), base.z()}, {q.w(), q.x(), q.y(), q.z()}};
}

/// Inserts from tip `start_m` along `d` by `travel_m`, recording each layer's events.
template <class Model, class Data>
std::vector<LayerEvents> insert(const Model& model, Data& data, const Eigen::Vector3d& start_m,
                                const Eigen::Vector3d& d, double travel_m) {
  std::vector<LayerEvents> events(data.interaction.layers.size());
  NeedleInputs inputs;
  const int ticks = static_cast<int>(travel_m / testing::kInsertionStepM);
  for (int tick = 1; tick <= ticks; ++tick) {
    inputs.base = pose_for_tip(start_m + tick * testing::kInsertionStepM * d, d);
    step(model, data, inputs);
    const Eigen::Vector3d tip = needle_tip_m(data.interaction.needle);
    for (std::size_t l = 0; l < events.size(); ++l) {
      const LayerState& state = data.interaction.layers[l];
      LayerEvents& e = events[l];
      e.closest_m = std::min(e.closest_m, detail::layer_hit(model.interaction, data.interaction, static_cast<int>(l),
                                                            tip, data.displacements_m)
                                              .distance_m);
      if (e.touched_tick < 0 && state.phase != LayerPhase::outside) {
        e.touched_tick = tick;
        e.touched_tip_m = tip;
        e.first_contact = state.contact;
      }
      if (e.punctured_tick < 0 && state.phase == LayerPhase::punctured) {
        e.punctured_tick = tick;
        e.punctured_tip_m = tip;
        e.punctured_base_m = node_position_m(data.interaction.needle.positions_m, 0);
        e.punctured_direction = needle_tip_direction(data.interaction.needle);
        e.punctured_displacements_m.assign(data.displacements_m.begin(), data.displacements_m.end());
      }
    }
  }
  return events;
}

enum class LiverOrder { reduced, full };

std::string order_name(const ::testing::TestParamInfo<LiverOrder>& info) {
  return info.param == LiverOrder::reduced ? "ReducedLiver" : "FullOrderLiver";
}

/// The full-order liver in time, as the station steps it: implicit Euler over the tissue step.
TissueSolverOptions dynamic_linear() {
  TissueSolverOptions options = testing::exact_linear_options();
  options.integrator = Integrator::implicit_euler;
  options.step_s = 1e-3 * kTissueEvery;
  return options;
}

/// The liver's two orders, built once: 24 vibration modes, and the full-order model.
struct LiverModels {
  ReducedModel reduced{nullptr};
  TetFemModel full = make_tet_fem_model(the_liver().liver.mesh, the_liver().scene, dynamic_linear()).value();
  LiverModels() {
    const Liver& l = the_liver();
    ReductionOptions reduction;
    reduction.source = ReducedBasisSource::linear_modes;
    reduction.force_kind = ReducedForceKind::linear;
    reduction.basis_size = 24;
    const ReducedBasis modes =
        make_modal_basis(l.liver.mesh, l.scene, testing::exact_linear_options(), reduction).value();
    ReducedSolverOptions options;
    options.integrator = ReducedIntegrator::quasi_static;
    reduced = make_reduced_model(l.liver.mesh, l.scene, testing::exact_linear_options(), modes, options).value();
  }
};

const LiverModels& the_models() {
  static const LiverModels models;
  return models;
}

/// Runs `run(model, data)` on a coupled needle of the given order, its tip at `start_m`.
template <class Run>
void with_coupled_needle(LiverOrder order, const NeedleTissueScene& scene, const Eigen::Vector3d& start_m,
                         const Eigen::Vector3d& d, Run run) {
  const NeedlePose base = pose_for_tip(start_m, d);
  if (order == LiverOrder::reduced) {
    const auto model = make_coupled_needle_model(NeedleParameters{}, scene, the_models().reduced,
                                                 the_liver().liver.mesh, 32, kTissueEvery)
                           .value();
    auto data = make_coupled_needle_data(model, base).value();
    run(model, data);
  } else {
    const auto model =
        make_coupled_needle_model(NeedleParameters{}, scene, the_models().full, 32, kTissueEvery).value();
    auto data = make_coupled_needle_data(model, base).value();
    run(model, data);
  }
}

/// The demo's approach: from in front and a little above, toward the tumour.
Eigen::Vector3d approach() { return -Eigen::Vector3d(0.0, 1.0, 0.25).normalized(); }

/// Where a line along d through `aim_m` enters the capsule at rest.
Eigen::Vector3d entry_m(const Eigen::Vector3d& aim_m, const Eigen::Vector3d& d) {
  const Liver& l = the_liver();
  const Eigen::Vector3d far_outside = aim_m - 0.5 * d;
  return first_crossing(l.capsule, l.rest_m, {}, far_outside, d).value();
}

double element_length_m() { return NeedleParameters{}.length_m / NeedleParameters{}.element_count; }

TEST(TissueSurfaces, AreClosedOutwardAndEncloseTheirElements) {
  const Liver& l = the_liver();
  const auto as_surface = [&](const TissueSurface& s) {
    TriSurface tri;
    tri.vertices_m = l.liver.mesh.nodes_m;
    tri.triangles = s.triangles;
    return validate_surface(tri);
  };
  double liver_m3 = 0.0, tumour_m3 = 0.0;
  for (std::size_t e = 0; e < l.liver.mesh.tets.size(); ++e) {
    const double v = signed_tet_volume_m3(l.liver.mesh, e);
    liver_m3 += v;
    if (l.liver.mesh.tet_regions[e] == static_cast<std::int32_t>(TissueRegion::tumour)) tumour_m3 += v;
  }
  const SurfaceReport capsule = as_surface(l.capsule), tumour = as_surface(l.tumour);
  std::printf("capsule: %zu triangles, %.1f mL; tumour: %zu triangles, %.2f mL\n", capsule.triangles,
              capsule.enclosed_volume_m3 * 1e6, tumour.triangles, tumour.enclosed_volume_m3 * 1e6);
  EXPECT_TRUE(capsule.consistently_oriented);
  EXPECT_TRUE(tumour.consistently_oriented);
  EXPECT_EQ(capsule.boundary_edges, 0u);
  EXPECT_EQ(tumour.boundary_edges, 0u);
  EXPECT_NEAR(capsule.enclosed_volume_m3, liver_m3, 1e-9 * liver_m3);  // positive: outward
  EXPECT_NEAR(tumour.enclosed_volume_m3, tumour_m3, 1e-9 * tumour_m3);
  EXPECT_GT(tumour_m3, 0.5 * 4.0 / 3.0 * std::numbers::pi * std::pow(l.liver.tumour_radius_m, 3));
  EXPECT_FALSE(region_boundary_surface(l.liver.mesh, 99).ok());
}

TEST(TissueSurfaces, NearestPointAndSideEqualTheBruteForceOnTheDeformedLiver) {
  const Liver& l = the_liver();
  const auto model = make_needle_tissue_model(NeedleParameters{}, liver_layers(vec(l.liver.tumour_centre_m)), l.rest_m);
  ASSERT_TRUE(model.ok()) << model.error().describe();
  auto data = make_needle_tissue_data(model.value(), pose_for_tip({0.0, 0.3, 0.0}, approach())).value();
  // A smooth deformation of up to 8 mm, with the hierarchies refitted to it.
  std::vector<double> u(l.rest_m.size());
  for (std::size_t n = 0; n < u.size() / 3; ++n) {
    const double x = l.rest_m[3 * n], y = l.rest_m[3 * n + 1], z = l.rest_m[3 * n + 2];
    u[3 * n] = 0.008 * std::sin(20.0 * y);
    u[3 * n + 1] = 0.006 * std::cos(15.0 * z);
    u[3 * n + 2] = 0.005 * std::sin(25.0 * x);
  }
  refresh_surfaces(model.value(), data, u);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Vector3d centre = vec(l.liver.tumour_centre_m);
  int inside[2] = {0, 0};
  for (int k = 0; k < 300; ++k) {
    // Half spread over the liver's whole box, half near the tumour.
    const double spread = k % 2 == 0 ? 0.15 : 0.03;
    const Eigen::Vector3d x = centre + spread * Eigen::Vector3d(unit(random), unit(random), unit(random));
    for (int layer = 0; layer < 2; ++layer) {
      const TissueSurface& s = layer == 0 ? l.capsule : l.tumour;
      const detail::SurfaceHit hit = detail::layer_hit(model.value(), data, layer, x, u);
      const double brute_m = surface_distance_m(s, l.rest_m, u, x);
      const bool is_inside = winding_number(s, l.rest_m, u, x) > 0.5;
      inside[layer] += is_inside ? 1 : 0;
      ASSERT_NEAR(std::abs(hit.distance_m), brute_m, 1e-12) << "layer " << layer << " point " << k;
      ASSERT_EQ(hit.distance_m < 0.0, is_inside) << "layer " << layer << " point " << k << " at " << brute_m;
      ASSERT_NEAR((x - hit.point_m).norm(), brute_m, 1e-12);
      ASSERT_NEAR(hit.normal.norm(), 1.0, 1e-12);
    }
  }
  std::printf("inside the capsule: %d of 300 points, inside the tumour: %d\n", inside[0], inside[1]);
  EXPECT_GT(inside[0], 30);  // both sides are exercised
  EXPECT_GT(inside[1], 5);
}

TEST(TissueSurfaces, BadSurfacesAreRefusedByField) {
  const Liver& l = the_liver();
  NeedleTissueScene scene = liver_layers(vec(l.liver.tumour_centre_m));
  scene.layers[1].surface = 2;
  auto refused = make_needle_tissue_model(NeedleParameters{}, scene, l.rest_m);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "scene.layers[1].surface");
  scene = liver_layers(vec(l.liver.tumour_centre_m));
  scene.surfaces[1].triangles[3][1] = static_cast<std::int32_t>(l.rest_m.size() / 3);
  refused = make_needle_tissue_model(NeedleParameters{}, scene, l.rest_m);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "scene.surfaces[1]");
  EXPECT_NE(refused.error().message.find("triangle 3"), std::string::npos) << refused.error().message;
  scene.surfaces[1].triangles.clear();
  EXPECT_FALSE(make_needle_tissue_model(NeedleParameters{}, scene, l.rest_m).ok());
}

class NeedleSurfaces : public ::testing::TestWithParam<LiverOrder> {};

/// How far the tip passed the surface where the needle's line meets it on the deformed liver.
double beyond_crossing_m(const TissueSurface& s, const LayerEvents& e) {
  const Liver& l = the_liver();
  const auto crossing =
      first_crossing(s, l.rest_m, e.punctured_displacements_m, e.punctured_base_m, e.punctured_direction);
  if (!crossing) return std::numeric_limits<double>::infinity();
  return (e.punctured_tip_m - *crossing).norm();
}

TEST_P(NeedleSurfaces, AimedAtTheTumourItPuncturesTheCapsuleThenTheTumourWhereItsLineMeetsThem) {
  const Liver& l = the_liver();
  const Eigen::Vector3d d = approach(), aim = vec(l.liver.tumour_centre_m), entry = entry_m(aim, d);
  const Eigen::Vector3d start = entry - kStartOutsideM * d;
  const double travel_m = (aim - start).norm();
  with_coupled_needle(GetParam(), liver_layers(entry), start, d, [&](const auto& model, auto& data) {
    const std::vector<LayerEvents> e = insert(model, data, start, d, travel_m);
    ASSERT_GT(e[0].punctured_tick, 0) << "the capsule was not punctured";
    ASSERT_GT(e[1].punctured_tick, e[0].punctured_tick)
        << "the tumour was not punctured after the capsule; touched at tick " << e[1].touched_tick << " of "
        << static_cast<int>(travel_m / testing::kInsertionStepM) << ", phase "
        << static_cast<int>(data.interaction.layers[1].phase) << ", contact force "
        << data.interaction.report.contact_force_n << " N, flags " << data.interaction.health.bits();
    const double capsule_m = beyond_crossing_m(l.capsule, e[0]), tumour_m = beyond_crossing_m(l.tumour, e[1]);
    std::printf(
        "capsule punctured %.2f mm past its crossing, tumour %.2f mm past its (element %.1f mm); "
        "tumour touched at insertion %.1f mm, punctured at %.1f mm\n",
        capsule_m * 1e3, tumour_m * 1e3, element_length_m() * 1e3, e[1].touched_tick * testing::kInsertionStepM * 1e3,
        e[1].punctured_tick * testing::kInsertionStepM * 1e3);
    EXPECT_LT(capsule_m, element_length_m());
    EXPECT_LT(tumour_m, element_length_m());
    EXPECT_EQ(data.interaction.report.punctures, 2);
    EXPECT_TRUE(data.interaction.health.healthy()) << "flags " << data.interaction.health.bits();
  });
}

TEST_P(NeedleSurfaces, ThreeMillimetresBesideTheTumourItPassesWithoutPuncturingIt) {
  const Liver& l = the_liver();
  const Eigen::Vector3d d = approach(), centre = vec(l.liver.tumour_centre_m);
  // Sideways (x, across the approach): 3 mm beyond the tumour's farthest vertex that way, so
  // that the line keeps at least 3 mm from every point of the tumour's surface.
  const Eigen::Vector3d side = d.cross(Eigen::Vector3d::UnitZ()).normalized();
  double reach_m = 0.0, depth_m = 0.0;
  for (const auto& t : l.tumour.triangles)
    for (const std::int32_t node : t) {
      reach_m = std::max(reach_m, (position_m(l.rest_m, {}, node) - centre).dot(side));
      depth_m = std::max(depth_m, (position_m(l.rest_m, {}, node) - centre).dot(d));
    }
  const Eigen::Vector3d aim = centre + (reach_m + kBesideM) * side, entry = entry_m(aim, d);
  const Eigen::Vector3d start = entry - kStartOutsideM * d;
  const double travel_m = (aim - start).dot(d) + depth_m + 0.01;  // past the tumour's far side
  // The tangent plane at the tumour's pole facing the needle, the layer surfaces replace.
  const Eigen::Vector3d pole = centre - l.liver.tumour_radius_m * d;
  for (bool plane : {false, true}) {
    const auto tumour_plane = plane ? std::optional(std::pair(pole, Eigen::Vector3d(-d))) : std::nullopt;
    NeedleTissueScene scene = liver_layers(entry, tumour_plane);
    scene.layers[0].surface_friction_coefficient = 0.7;  // the tip holds where it meets the capsule
    with_coupled_needle(GetParam(), scene, start, d, [&](const auto& model, auto& data) {
      const std::vector<LayerEvents> e = insert(model, data, start, d, travel_m);
      EXPECT_GT(e[0].punctured_tick, 0);
      if (plane) {
        std::printf("tumour as its tangent plane: %d punctures\n", data.interaction.report.punctures);
        EXPECT_GT(e[1].punctured_tick, 0) << "the plane's shortcut no longer shows";
      } else {
        std::printf("tumour as its surface: %d puncture; the tip passed %.2f mm from the tumour's surface\n",
                    data.interaction.report.punctures, e[1].closest_m * 1e3);
        EXPECT_EQ(e[1].touched_tick, -1) << "the needle touched the tumour it passes beside";
        EXPECT_EQ(data.interaction.report.punctures, 1);
        EXPECT_GT(e[1].closest_m, 0.0);
        EXPECT_LT(e[1].closest_m, 2.0 * kBesideM) << "the needle strayed from its path beside the tumour";
      }
    });
  }
}

TEST_P(NeedleSurfaces, AnObliqueEntryTouchesTheCapsuleWhereItsLineMeetsIt) {
  const Liver& l = the_liver();
  // 30 degrees off the capsule's normal where the approach toward the tumour enters it, on a
  // capsule whose friction holds the tip there (tan 30 degrees < 0.7: it does not slide).
  const Eigen::Vector3d aim = vec(l.liver.tumour_centre_m), entry = entry_m(aim, approach());
  const auto bare = make_needle_tissue_model(NeedleParameters{}, liver_layers(entry), l.rest_m).value();
  const auto bare_data =
      make_needle_tissue_data(bare, pose_for_tip(entry + 0.1 * Eigen::Vector3d::UnitY(), approach())).value();
  const Eigen::Vector3d n = detail::layer_hit(bare, bare_data, 0, entry, {}).normal;
  const Eigen::Vector3d across = n.cross(Eigen::Vector3d::UnitX()).normalized();
  const double tilt = 30.0 * std::numbers::pi / 180.0;
  const Eigen::Vector3d d = -(std::cos(tilt) * n + std::sin(tilt) * across);
  const Eigen::Vector3d crossing = first_crossing(l.capsule, l.rest_m, {}, entry - 0.05 * d, d).value();
  const Eigen::Vector3d start = crossing - kStartOutsideM * d;
  NeedleTissueScene scene = liver_layers(crossing);
  scene.layers[0].surface_friction_coefficient = 0.7;
  with_coupled_needle(GetParam(), scene, start, d, [&](const auto& model, auto& data) {
    const std::vector<LayerEvents> e = insert(model, data, start, d, 0.03);
    ASSERT_GT(e[0].touched_tick, 0);
    ASSERT_GT(e[0].punctured_tick, 0);
    const double touch_m = (e[0].first_contact.rest_m - crossing).norm();
    const double hole_m = (data.interaction.layers[0].hole.rest_m - crossing).norm();
    const double angle_deg = std::acos(std::clamp(-d.dot(n), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    std::printf(
        "%.0f degrees off the normal: touched %.1f um from the line's crossing, holed %.1f um from it, "
        "the tip %.2f mm past the crossing on the deformed liver at the puncture\n",
        angle_deg, touch_m * 1e6, hole_m * 1e6, beyond_crossing_m(l.capsule, e[0]) * 1e3);
    EXPECT_LT(touch_m, 0.5e-3);  // the first touch: one 20 um tick's travel and the tip's bend
    EXPECT_LT(hole_m, 1e-3);     // where it touched: the tip stuck
    EXPECT_LT(beyond_crossing_m(l.capsule, e[0]), element_length_m());
  });
}

TEST_P(NeedleSurfaces, TicksAllocateNothingAndRepeatBitwise) {
  const Liver& l = the_liver();
  const Eigen::Vector3d d = approach(), aim = vec(l.liver.tumour_centre_m), entry = entry_m(aim, d);
  const Eigen::Vector3d start = entry - kStartOutsideM * d;
  std::vector<double> runs[2];
  for (std::vector<double>& run : runs)
    with_coupled_needle(GetParam(), liver_layers(entry), start, d, [&](const auto& model, auto& data) {
      insert(model, data, start, d, 0.01);  // through the capsule
      NeedleInputs inputs;
      const testing::AllocationGuard counter;
      for (int tick = 1; tick <= 300; ++tick) {
        inputs.base = pose_for_tip(start + (0.01 + tick * testing::kInsertionStepM) * d, d);
        step(model, data, inputs);
      }
      EXPECT_EQ(counter.allocations(), 0u);
      run.assign(data.interaction.needle.positions_m.begin(), data.interaction.needle.positions_m.end());
      run.insert(run.end(), data.displacements_m.begin(), data.displacements_m.end());
      EXPECT_EQ(data.interaction.report.punctures, 1);
    });
  ASSERT_EQ(runs[0].size(), runs[1].size());
  EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(double)), 0);
}

INSTANTIATE_TEST_SUITE_P(LiverOrders, NeedleSurfaces, ::testing::Values(LiverOrder::reduced, LiverOrder::full),
                         order_name);

}  // namespace
}  // namespace nav
