#pragma once
// The blocked cubature kernels of a ReducedModel: the sampled tetrahedra kSampleLanes at a
// time in structure-of-arrays form, gathering U_S q and scattering U_S^T f block by block,
// the corotational tangent in G-form (V = G blockdiag(R^T) U_s, K += V^T V). The lane loops
// run in the model's instruction-set variant (reduced_lane_kernels.hpp); the St
// Venant-Kirchhoff stresses here. Every lane's arithmetic is the same whatever the vector
// width, and every sum runs in an order written in the code: results are bitwise repeatable
// on every architecture and instruction set. noexcept, allocation-free. Internal to
// rtlib/nav/reduced.
#include <cstddef>
#include <span>

#include "nav/core/kernel_isa.hpp"
#include "nav/reduced/reduced_lane_kernels.hpp"
#include "nav/reduced/reduced_tables.hpp"

namespace nav::detail {

/// The state a reduced force is evaluated at: coordinates q and diaphragm displacement d.
struct ReducedState {
  std::span<const double> q;
  const double* prescribed_m;  ///< 3 values
};

/// Adds each lane's reduced corotational force U_s^T f_s, f_s = -R G^T G (R^T x - X), to
/// work.lane_forces; with `remainder`, the non-linear remainder U_s^T (f_s + w K_s u_s)
/// instead. The rotations of all samples are found together (their iterations interleave).
/// A sample with det F <= 0 keeps its previous rotation. Returns how many had det F <= 0.
int add_corotational_forces(const ReducedTables& t, const ReducedState& state, bool remainder,
                            const SampleWork& work) noexcept;

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

/// The lane kernels of an instruction set (`best` resolved first); `isa` must be available.
const ReducedLaneKernels& reduced_lane_kernels(KernelIsa isa) noexcept;

/// The sample tables of `t` as the lane kernels read them.
CubatureView cubature_view(const ReducedTables& t) noexcept;

}  // namespace nav::detail
