#pragma once
// What the operating loop's tests share: their 8 x 2 x 2 cm beam breathes through its x = 8 cm
// face, the diaphragm following a respiratory marker that rises and falls along the tracker's
// z; the tumour is the mesh node nearest the beam's centre.
#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav::testing {

constexpr double kBreathingPeriodS = 2.0, kMarkerAmplitudeM = 0.006, kMarkerMeanM = 0.1;
inline const Eigen::Vector3d kDiaphragmPerMarker{0.25, 0.0, 1.2};

/// The marker's displacement along the tracker's z at time t, for a breath `depth` times the nominal one.
inline double marker_m(TimeNs t, double depth) {
  return kMarkerMeanM + depth * kMarkerAmplitudeM *
                            std::sin(2.0 * std::numbers::pi * static_cast<double>(t) * 1e-9 / kBreathingPeriodS);
}

/// The diaphragm's displacement that goes with marker_m.
inline Point3 diaphragm_at(TimeNs t, double depth) {
  const Eigen::Vector3d d = kDiaphragmPerMarker * (marker_m(t, depth) - kMarkerMeanM);
  return {d[0], d[1], d[2]};
}

/// The node of `mesh` nearest `point` (the first of equals).
inline std::int32_t nearest_node(const TetMesh& mesh, const Point3& point) {
  double best = 1e300;
  std::int32_t nearest = 0;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    const auto& x = mesh.nodes_m[n];
    const double d = std::hypot(x[0] - point[0], x[1] - point[1], x[2] - point[2]);
    if (d < best) best = d, nearest = static_cast<std::int32_t>(n);
  }
  return nearest;
}

/// Steps `full` (from rest) with the diaphragm at diaphragm_at(t, depth(t)) and the load scale
/// load_scale(i) at step i, every `step_ns`: returns `node`'s position after every step, and
/// appends every snapshot_every-th step's displacements from rest to `snapshots` (if given).
template <class Depth, class LoadScale>
std::vector<Point3> breathe(const TetFemModel& full, TimeNs step_ns, Depth depth, LoadScale load_scale, int steps,
                            std::int32_t node, std::vector<double>* snapshots, int snapshot_every) {
  auto data = make_tet_fem_data(full).value();
  const auto rest = full.rest_positions_m();
  std::vector<Point3> out;
  for (int i = 0; i < steps; ++i) {
    TissueInputs inputs;
    inputs.load_scale = load_scale(i);
    inputs.prescribed_displacement_m = diaphragm_at(i * step_ns, depth(i * step_ns));
    step(full, data, inputs);
    const auto n = static_cast<std::size_t>(node);
    out.push_back({data.positions_m[3 * n], data.positions_m[3 * n + 1], data.positions_m[3 * n + 2]});
    if (snapshots != nullptr && (i + 1) % snapshot_every == 0)
      for (std::size_t k = 0; k < rest.size(); ++k) snapshots->push_back(data.positions_m[k] - rest[k]);
  }
  return out;
}

}  // namespace nav::testing
