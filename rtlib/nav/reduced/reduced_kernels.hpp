#pragma once
// The blocked cubature kernels of a ReducedModel: the sampled tetrahedra kSampleLanes at a
// time in structure-of-arrays form (plain loops over the lanes, which the compiler
// vectorizes), gathering U_S q and scattering U_S^T f block by block, the corotational
// tangent in G-form (V = G blockdiag(R^T) U_s, K += V^T V). Every lane's arithmetic is the
// same whatever the vector width, and every sum runs in an order written here: results are
// bitwise repeatable on every architecture. noexcept, allocation-free. Internal to
// rtlib/nav/reduced.
#include <cstddef>
#include <span>

#include "nav/reduced/reduced_tables.hpp"

namespace nav::detail {

/// The state a reduced force is evaluated at: coordinates q and diaphragm displacement d.
struct ReducedState {
  std::span<const double> q;
  const double* prescribed_m;  ///< 3 values
};

/// Where the cubature kernels work, carved by the caller (sizes in doubles; `lanes` is
/// kSampleLanes sample_blocks). Per-sample values are k-major over all lanes: value k of
/// sample s at [k lanes + s].
struct SampleWork {
  double* displacements;  ///< 12 lanes: the samples' vertex displacements (written)
  double* rotations;      ///< 9 lanes, column-major 3x3: the last good rotations (read and written)
  double* gradients;      ///< 10 lanes: 9 of deformation gradients (the polar iterates, in place), 1 of det F > 0 flags
  double* lane_forces;    ///< reduced forces per lane, [j kSampleLanes + l] (+ r kSampleLanes b when per_block)
  bool per_block = false; ///< each block its own r kSampleLanes lane forces (else one set for all)
};

/// Adds each lane's reduced corotational force U_s^T f_s, f_s = -R G^T G (R^T x - X), to
/// work.lane_forces; with `remainder`, the non-linear remainder U_s^T (f_s + w K_s u_s)
/// instead. The rotations of all samples are found together (their iterations interleave).
/// A sample with det F <= 0 keeps its previous rotation. Returns how many had det F <= 0.
int add_corotational_forces(const ReducedTables& t, const ReducedState& state, bool remainder, const SampleWork& work) noexcept;

/// The same for the St Venant-Kirchhoff law (with the tables' incompressibility gain).
int add_stvk_forces(const ReducedTables& t, const ReducedState& state, bool remainder, const SampleWork& work) noexcept;

/// Doubles of the tangent workspace of add_corotational_tangent_block: the rows V of a block,
/// 6 kSampleLanes x (r rounded up to a tile).
std::size_t corotational_tangent_work_size(int r) noexcept;

/// Adds sum over the lanes of block b of V^T V, V = G blockdiag(R^T) U_s, to the upper
/// triangle (at least) of the row-major r x r `tangent`, with the rotations of work.
void add_corotational_tangent_block(const ReducedTables& t, int b, const SampleWork& work, std::span<double> rows_work,
                                    std::span<double> tangent) noexcept;

/// Adds the lanes' reduced St Venant-Kirchhoff tangents U_s^T w K_s(F) U_s of block b (at
/// the displacements add_stvk_forces left in work) to `tangent`, sample by sample.
void add_stvk_tangent_block(const ReducedTables& t, int b, const SampleWork& work, std::span<double> tangent) noexcept;

/// Replaces the `lanes` 3x3 matrices of `a` (k-major: entry (i, j) of matrix n at
/// [(3 j + i) lanes + n], each with det > 0) by the orthogonal factors of their polar
/// decompositions: kPolarIterations Newton iterations R <- (g R + R^-T / g) / 2, all matrices
/// interleaved, with the Frobenius scaling g = (|R^-T| / |R|)^(1/2) approximated to about
/// 1e-3 without a square root (any positive g converges; this one keeps the loop free of
/// library calls, so that it vectorizes).
void polar_rotations_interleaved(double* a, std::size_t lanes) noexcept;

/// out[v] = row v of the panels times q, plus the lift panels times d when not empty, for the
/// `values` values of a ReducedDisplaySet (panels of kSampleLanes values: row v, column j at
/// [(v / kSampleLanes) r + j) kSampleLanes + v % kSampleLanes]). Each value sums over the
/// columns in order.
void panel_times(std::span<const double> panels, std::span<const double> lift_panels, const double* q, int r,
                 const double* prescribed_m, std::span<double> out) noexcept;

}  // namespace nav::detail
