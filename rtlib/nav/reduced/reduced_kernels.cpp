#include "nav/reduced/reduced_kernels.hpp"

#include "nav/tissue/st_venant_kirchhoff.hpp"

namespace nav::detail {
namespace {

constexpr int L = kSampleLanes;

const ReducedLaneKernels& kernels_of(const ReducedTables& t) { return *t.lane_kernels; }

LaneState lane_state(const ReducedState& state) { return {state.q.data(), state.prescribed_m}; }

/// Start of block b of a blocked table with `per_sample` values per sample.
const double* block(const std::vector<double>& table, int b, int per_sample) {
  return table.data() + static_cast<std::size_t>(b) * static_cast<std::size_t>(per_sample) * L;
}

/// Lane l of block b's deformation gradient in work (entry (i, j) at [(3 j + i) lanes + s]).
Eigen::Matrix3d lane_gradient(const ReducedTables& t, const SampleWork& work, int b, int l) {
  const std::size_t lanes = static_cast<std::size_t>(t.sample_blocks) * L,
                    s = static_cast<std::size_t>(b) * L + static_cast<std::size_t>(l);
  Eigen::Matrix3d m;
  for (std::size_t k = 0; k < 9; ++k)
    m(static_cast<Eigen::Index>(k % 3), static_cast<Eigen::Index>(k / 3)) = work.gradients[k * lanes + s];
  return m;
}

/// Sample index of lane l of block b.
std::size_t sample(int b, int l) { return static_cast<std::size_t>(b) * L + static_cast<std::size_t>(l); }

}  // namespace

const ReducedLaneKernels& reduced_lane_kernels(KernelIsa isa) noexcept {
  switch (resolve_kernel_isa(isa)) {
#if NAV_KERNEL_ISA_X86
    case KernelIsa::avx2:
      return reduced_lane_kernels_avx2;
    case KernelIsa::avx512:
      return reduced_lane_kernels_avx512;
#endif
    default:
      return reduced_lane_kernels_baseline;
  }
}

CubatureView cubature_view(const ReducedTables& t) noexcept {
  return {t.r,
          t.sample_blocks,
          t.has_lift,
          t.sample_rows.data(),
          t.has_lift ? t.sample_lift.data() : nullptr,
          t.sample_rest_m.data(),
          t.sample_gradients.data(),
          t.sample_root_stiffness.data()};
}

int add_corotational_forces(const ReducedTables& t, const ReducedState& state, bool remainder,
                            const SampleWork& work) noexcept {
  return kernels_of(t).corotational_forces(cubature_view(t), lane_state(state), remainder, work);
}

int add_stvk_forces(const ReducedTables& t, const ReducedState& state, bool remainder,
                    const SampleWork& work) noexcept {
  const ReducedLaneKernels& kernels = kernels_of(t);
  const CubatureView view = cubature_view(t);
  const int inverted = kernels.deformations(view, lane_state(state), work);
  for (int b = 0; b < t.sample_blocks; ++b) {
    const double* g = block(t.sample_gradients, b, 12);
    const double* weight_volume = block(t.sample_weight_volume, b, 1);
    LaneForces f;
    for (int l = 0; l < L; ++l) {
      const Eigen::Matrix3d stress = stvk_stress(lane_gradient(t, work, b, l), t.sample_lame[sample(b, l)], t.gain_pa);
      const double scale = -weight_volume[l];
      for (int a = 0; a < 4; ++a) {
        const Eigen::Vector3d out =
            scale * (stress * Eigen::Vector3d(g[(3 * a) * L + l], g[(3 * a + 1) * L + l], g[(3 * a + 2) * L + l]));
        for (int c = 0; c < 3; ++c) f[3 * a + c][l] = out[c];
      }
    }
    kernels.add_block_forces(view, b, remainder, f, work);
  }
  return inverted;
}

std::size_t corotational_tangent_work_size(int r) noexcept {
  return static_cast<std::size_t>(6 * L * ((r + kTangentTile - 1) / kTangentTile * kTangentTile));
}

void add_corotational_tangent_block(const ReducedTables& t, int b, const SampleWork& work, std::span<double> rows_work,
                                    std::span<double> tangent) noexcept {
  kernels_of(t).add_corotational_tangent_block(cubature_view(t), b, work, rows_work.data(), tangent.data());
}

void add_stvk_tangent_block(const ReducedTables& t, int b, const SampleWork& work, std::span<double> tangent) noexcept {
  const int r = t.r;
  const double* rows = block(t.sample_rows, b, 12 * r);
  const double* g = block(t.sample_gradients, b, 12);
  const double* weight_volume = block(t.sample_weight_volume, b, 1);
  for (int l = 0; l < L && sample(b, l) < static_cast<std::size_t>(t.sample_count); ++l) {
    auto row = [&](int i, int j) { return rows[static_cast<std::size_t>((i * r + j) * L + l)]; };
    auto gradient = [&](int a) {
      return Eigen::Vector3d(g[(3 * a) * L + l], g[(3 * a + 1) * L + l], g[(3 * a + 2) * L + l]);
    };
    const Eigen::Matrix3d f = lane_gradient(t, work, b, l);
    const LameParameters& lame = t.sample_lame[sample(b, l)];
    const Eigen::Matrix3d tangent_stress = stvk_tangent_stress(f, lame);
    for (int j = 0; j < r; ++j) {
      Eigen::Matrix3d df = Eigen::Matrix3d::Zero();
      for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 3; ++c)
          for (int k = 0; k < 3; ++k) df(c, k) += row(3 * a + c, j) * g[(3 * a + k) * L + l];
      const Eigen::Matrix3d dp = weight_volume[l] * stvk_stress_derivative(f, df, tangent_stress, lame, t.gain_pa);
      double column[12];
      for (int a = 0; a < 4; ++a) {
        const Eigen::Vector3d out = dp * gradient(a);
        for (int c = 0; c < 3; ++c) column[3 * a + c] = out[c];
      }
      for (int i = 0; i < 12; ++i)
        for (int k = 0; k < r; ++k) tangent[static_cast<std::size_t>(k * r + j)] += row(i, k) * column[i];
    }
  }
}

}  // namespace nav::detail
