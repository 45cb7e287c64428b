#pragma once
// The liver a running station navigates in, built from a scene at start-up: the embedded
// default liver held at its attachments, the top 2 cm of its boundary a diaphragm region
// that breathing moves, its tumour as an observed point; and the operating loop on it: a
// modal reduced model (vibration modes, corotational cubature trained on full-order
// quasi-static steps under diaphragm moves) with the Kalman filter on the tumour. Also the
// breathing geometry the simulated devices and the loop share. Init-time code.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "nav/core/error.hpp"
#include "nav/fusion/reduced_kalman.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/station/scene.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav::station {

/// How the respiratory marker and the diaphragm move together: the marker rises along the
/// tracker's z from its mean, the diaphragm follows by diaphragm_per_marker.
struct BreathingGeometry {
  Eigen::Vector3d marker_rest_m{0.0, 0.15, 0.1};        ///< the marker at mid-breath (tracker frame)
  Eigen::Vector3d diaphragm_per_marker{0.0, 0.0, 1.0};  ///< diaphragm displacement per metre of marker motion
};

/// The station's liver: mesh, tissue scene (attachments fixed, diaphragm prescribed, no
/// gravity: the rest shape is the shape in the body) and the tumour.
struct StationLiver {
  TetMesh mesh;
  TissueScene scene;
  Point3 tumour_m{};         ///< the tumour's centre at rest, model frame
  ObservedPoint tumour;      ///< the same point as a barycentric point of one tetrahedron
};

/// The generated liver of `scene` (liver.mesh: generated; its material). Errors name the
/// scene file and the `liver` section.
Result<StationLiver> make_station_liver(const Scene& scene);

/// How the station's reduced liver is built.
struct StationLoopSettings {
  int basis_size = 16;             ///< vibration modes kept
  int max_cubature_samples = 32;   ///< corotational cubature tetrahedra
  TimeNs needle_max_extrapolation_ns = 100 * kNsPerMs;  ///< display latency plus the tracker's delay
  /// The filter's correction: its standard deviation per mode as a fraction of the training
  /// envelope, and its correlation time. The training moves the diaphragm only, which the
  /// lift carries; the modes' own envelope is small, and 3 times it lets the filter take up
  /// the demo's surrogate error (tumour RMS on a 6 s demo: 1.09 mm at 1 time, 0.77 mm at 3,
  /// 0.80 mm at 6, 0.99 mm at 10).
  double correction_fraction = 3.0;
  double correlation_time_s = 2.0;
  double gate_chi_square = 16.27;  ///< observations further from the prediction are rejected
};

/// The needle base (holder) in the needle marker's frame, T_marker_base: the needle points
/// along the marker's -z from the marker's origin (the tip straight at (0, 0, -length_m)),
/// and along the base frame's +x, as the needle models lie.
RigidPose needle_base_in_marker();

/// The operating loop on `liver` at the scene's rates and latency, the tracker frame equal to
/// the model frame. With `needle:` the loop steps the scene's flexible needle coupled to its
/// reduced liver (at the loop rate, its base at the needle marker * needle_base_in_marker());
/// without it, a rigid needle of 0.15 m.
Result<OperatingLoopModel> make_station_loop(const StationLiver& liver, const Scene& scene, const BreathingGeometry& breathing,
                                             const StationLoopSettings& settings);

}  // namespace nav::station
