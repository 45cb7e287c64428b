#pragma once
// The lane kernels of the reduced cubature, compiled once per instruction set from
// reduced_lane_kernels.isa.cpp (nav/core/kernel_isa.hpp): raw views of a ReducedModel's
// blocked sample tables and the table of entry points a model calls through. Plain data
// only: the kernel sources include this header and nothing with inline functions. Internal
// to rtlib/nav/reduced.
#include <cstddef>

namespace nav::detail {

/// Sampled tetrahedra per block of the cubature kernels (the lanes of their loops).
inline constexpr int kSampleLanes = 8;

/// Columns per tile of the tangent update.
inline constexpr int kTangentTile = 8;

/// The blocked sample tables of a ReducedTables (layouts there), as raw pointers.
struct CubatureView {
  int r = 0;
  int sample_blocks = 0;
  bool has_lift = false;
  const double* sample_rows = nullptr;
  const double* sample_lift = nullptr;  ///< null without a lift
  const double* sample_rest_m = nullptr;
  const double* sample_gradients = nullptr;
  const double* sample_root_stiffness = nullptr;
};

/// The state a reduced force is evaluated at: r coordinates q and the diaphragm displacement.
struct LaneState {
  const double* q = nullptr;
  const double* prescribed_m = nullptr;  ///< 3 values
};

/// Where the cubature kernels work, carved by the caller (sizes in doubles; `lanes` is
/// kSampleLanes sample_blocks). Per-sample values are k-major over all lanes: value k of
/// sample s at [k lanes + s].
struct SampleWork {
  double* displacements;  ///< 12 lanes: the samples' vertex displacements (written)
  double* rotations;      ///< 9 lanes, column-major 3x3: the last good rotations (read and written)
  double* gradients;      ///< 10 lanes: 9 of deformation gradients (the polar iterates, in place), 1 of det F > 0 flags
  double* lane_forces;    ///< reduced forces per lane, [j kSampleLanes + l] (+ r kSampleLanes b when per_block)
  bool per_block = false;  ///< each block its own r kSampleLanes lane forces (else one set for all)
};

/// Per-lane forces of one block: component i of lane l at [i][l].
using LaneForces = double[12][kSampleLanes];

/// The entry points of one instruction set's variant; every variant computes the same bits.
struct ReducedLaneKernels {
  /// Adds each lane's U_s^T f_s, f_s = -R G^T G (R^T x - X), to work.lane_forces (with
  /// `remainder`: U_s^T (f_s + w K_s u_s)); a sample with det F <= 0 keeps its previous
  /// rotation. Returns how many had det F <= 0.
  int (*corotational_forces)(const CubatureView& view, const LaneState& state, bool remainder,
                             const SampleWork& work) noexcept;
  /// The displacements u = U_s q + L_s d and deformation gradients of every block into
  /// work (det F > 0 flags in row 9). Returns how many had det F <= 0.
  int (*deformations)(const CubatureView& view, const LaneState& state, const SampleWork& work) noexcept;
  /// Adds U_s^T f of block b (with `remainder`, U_s^T (f + w K_s u)) to its lane forces.
  void (*add_block_forces)(const CubatureView& view, int b, bool remainder, const LaneForces& f,
                           const SampleWork& work) noexcept;
  /// Adds sum over block b's lanes of V^T V, V = G blockdiag(R^T) U_s, to the upper triangle
  /// (at least) of the row-major r x r `tangent`; `rows_work` holds 6 kSampleLanes rows of r
  /// rounded up to kTangentTile.
  void (*add_corotational_tangent_block)(const CubatureView& view, int b, const SampleWork& work, double* rows_work,
                                         double* tangent) noexcept;
  /// Replaces the `lanes` 3x3 matrices of `a` (entry (i, j) of matrix n at [(3 j + i) lanes + n],
  /// det > 0) by the orthogonal factors of their polar decompositions (scaled Newton
  /// iterations, interleaved, as many as polar_iterations.hpp says).
  void (*polar_rotations)(double* a, std::size_t lanes) noexcept;
  /// out[v] = row v of the display panels times q (+ the lift panels times d when not null).
  void (*panel_times)(const double* panels, const double* lift_panels, const double* q, int r,
                      const double* prescribed_m, double* out, std::size_t values) noexcept;
};

extern const ReducedLaneKernels reduced_lane_kernels_baseline;
extern const ReducedLaneKernels reduced_lane_kernels_avx2;    ///< x86-64 builds only
extern const ReducedLaneKernels reduced_lane_kernels_avx512;  ///< x86-64 builds only

}  // namespace nav::detail
