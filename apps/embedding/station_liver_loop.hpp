#pragma once
// Start-up of the embedding example: the station software builds, from navrt alone, the liver
// it navigates in (the embedded default liver held at its attachments, the top 2 cm of its
// boundary a diaphragm that breathing moves, the tumour as an observed point), the operating
// loop on it (16 vibration modes with corotational cubature trained on full-order
// quasi-static solves, the reduced Kalman filter on the tumour), and the full-order
// quasi-static answer to every diaphragm lift that the example scores the loop against.
// Init-time code: it allocates and returns errors; nothing here runs on the real-time thread.
#include <vector>

#include <Eigen/Core>

#include "nav/core/error.hpp"
#include "nav/fusion/reduced_kalman.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace embedding {

/// The liver: mesh, supports (attachments fixed, diaphragm prescribed, no gravity: the rest
/// shape is the shape in the body) and the tumour.
struct Liver {
  nav::TetMesh mesh;
  nav::TissueScene scene;
  nav::ObservedPoint tumour;      ///< the tumour's centre in its tetrahedron
  Eigen::Vector3d tumour_rest_m;  ///< the same point at rest (model frame)
};

/// The embedded default liver at `element_size_m`, with its tumour.
nav::Result<Liver> make_liver(double element_size_m);

/// Where the full-order model puts the tumour for a diaphragm lift along z: quasi-static
/// corotational solves on a regular grid of lifts, interpolated linearly in between.
class TumourTruth {
 public:
  /// Solves the full-order model at `count` lifts evenly spread over [-max_lift_m, max_lift_m].
  static nav::Result<TumourTruth> solve(const Liver& liver, double max_lift_m, int count);
  /// The tumour's centre (model frame) under a lift of `lift_m` (clamped to the grid).
  Eigen::Vector3d at(double lift_m) const;

 private:
  double min_m_ = 0.0, step_m_ = 0.0;
  std::vector<Eigen::Vector3d> tumour_m_;
};

/// The loop's rates and geometry that the station software chooses.
struct LoopSettings {
  nav::TimeNs tick_period_ns = nav::kNsPerMs;  ///< 1 kHz
  int tissue_every_ticks = 10;                 ///< the liver at 100 Hz
  nav::TimeNs display_latency_ns = 50 * nav::kNsPerMs;
  double needle_length_m = 0.15;         ///< the tip is at -length along the marker's z
  double respiratory_reference_m = 0.0;  ///< marker height (tracker z) at rest
  double observation_std_m = 1e-3;       ///< the ultrasound's tumour point, per axis
  double tracker_rate_hz = 60.0;
};

/// The operating loop on `liver`: reduced liver, filter and loop options. The tracker frame is
/// the model frame and the diaphragm follows the respiratory marker's z one to one.
nav::Result<nav::OperatingLoopModel> make_loop(const Liver& liver, const LoopSettings& settings);

}  // namespace embedding
