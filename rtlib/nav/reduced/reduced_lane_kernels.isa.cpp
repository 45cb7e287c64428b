// The lane kernels of the reduced cubature, compiled once per instruction set (see
// nav/core/kernel_isa_variant.hpp): the sampled tetrahedra kSampleLanes at a time in
// structure-of-arrays form, plain loops over the lanes that the compiler vectorizes to the
// variant's width, every sum in an order written here.
#include "nav/reduced/reduced_lane_kernels.hpp"
#include "nav/core/kernel_isa_variant.hpp"
#include "nav/tissue/polar_iterations.hpp"

namespace nav::detail::NAV_KERNEL_ISA_NAMESPACE {
namespace {

constexpr int L = kSampleLanes;

using Index = std::size_t;

Index index(int value) { return static_cast<Index>(value); }

/// Start of block b of a blocked table with `per_sample` values per sample.
const double* block(const double* table, int b, int per_sample) { return table + index(b) * index(per_sample) * L; }

int padded(int r) { return (r + kTangentTile - 1) / kTangentTile * kTangentTile; }

/// Per-sample values of block b in a k-major table over all lanes: value k of lane l at [k stride + l].
struct Lanes {
  double* p;
  Index stride;
  double& operator()(int k, int l) const { return p[index(k) * stride + index(l)]; }
};

Index lane_count(const CubatureView& t) { return index(t.sample_blocks) * L; }

Lanes lanes_of(double* table, const CubatureView& t, int b) { return {table + index(b) * L, lane_count(t)}; }

/// a b + c rounded once: a fused multiply-add on every instruction set (see kernel_isa.hpp).
double fused(double a, double b, double c) { return __builtin_fma(a, b, c); }

/// Loops whose lanes are unrolled and carry sums across the loop: the lanes are vectorized
/// (straight-line), not the loop (GCC would otherwise vectorize it as in-order reductions).
#if defined(__GNUC__) && !defined(__clang__)
#define NAV_LANES_NOT_LOOP __attribute__((optimize("no-tree-loop-vectorize")))
#else
#define NAV_LANES_NOT_LOOP
#endif

/// u = U_s q + L_s d for the lanes of block b: each lane sums over the basis columns in order.
NAV_LANES_NOT_LOOP void gather(const CubatureView& t, int b, const LaneState& state, const Lanes& u) {
  const int r = t.r;
  const double* rows = block(t.sample_rows, b, 12 * r);
  const double* q = state.q;
  for (int a = 0; a < 4; ++a) {
    double acc[3][L] = {};
    for (int j = 0; j < r; ++j) {
      const double qj = q[j];
      for (int c = 0; c < 3; ++c) {
        const double* row = rows + index(((3 * a + c) * r + j) * L);
        for (int l = 0; l < L; ++l) acc[c][l] = fused(row[l], qj, acc[c][l]);
      }
    }
    if (t.has_lift) {
      const double* lift = block(t.sample_lift, b, 36);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) {
          const double* row = lift + ((3 * a + c) * 3 + k) * L;
          const double dk = state.prescribed_m[k];
          for (int l = 0; l < L; ++l) acc[c][l] = fused(row[l], dk, acc[c][l]);
        }
    }
    for (int c = 0; c < 3; ++c)
      for (int l = 0; l < L; ++l) u(3 * a + c, l) = acc[c][l];
  }
}

/// Basis columns summed together by basis_sums: their sums stay in registers while each
/// basis row's stretch of them is read in one run.
constexpr int kColumnsTogether = 8;

/// Calls out(j0, count, sums) with sums[j][l] = sum_i U_s(i, j) f(i) per lane, i in order,
/// for the `Width` (or, with Width 0, `width`) basis columns from j0 of the block whose rows
/// start at `rows`.
template <int Width, class Out>
void basis_sums(const double* rows, int r, int j0, int width, const double (*f)[L], const Out& out) {
  const int count = Width > 0 ? Width : width;
  double sums[kColumnsTogether][L] = {};
  for (int i = 0; i < 12; ++i) {
    const double* row = rows + index((i * r + j0) * L);
#pragma GCC unroll 8
    for (int j = 0; j < count; ++j)
      for (int l = 0; l < L; ++l) sums[j][l] = fused(row[j * L + l], f[i][l], sums[j][l]);
  }
  out(j0, count, sums);
}

/// basis_sums of f for every run of kColumnsTogether basis columns (the last one shorter).
template <class Out>
void for_basis_sums(const double* rows, int r, const double (*f)[L], const Out& out) {
  int j0 = 0;
  for (; j0 + kColumnsTogether <= r; j0 += kColumnsTogether)
    basis_sums<kColumnsTogether>(rows, r, j0, kColumnsTogether, f, out);
  if (j0 < r) basis_sums<0>(rows, r, j0, r - j0, f, out);
}

/// lane_forces[j][l] += sum_i U_s(i, j) f(i) per lane, i in order.
void scatter(const CubatureView& t, int b, const LaneForces& f, double* __restrict lane_forces) {
  const int r = t.r;
  for_basis_sums(block(t.sample_rows, b, 12 * r), r, f,
                 [&](int j0, int width, const double(&sums)[kColumnsTogether][L]) {
                   for (int j = 0; j < width; ++j)
                     for (int l = 0; l < L; ++l) lane_forces[(j0 + j) * L + l] += sums[j][l];
                 });
}

/// The deformation gradients F = I + sum_a u_a g_a^T of block b's lanes (column-major), and
/// 1 or 0 as det F > 0 or not in row 9 of `f`; with `identity_when_inverted`, a lane with
/// det F <= 0 gets the identity. Returns how many had det F <= 0.
NAV_LANES_NOT_LOOP int deformation(const CubatureView& t, int b, const Lanes& u, const Lanes& f,
                                   bool identity_when_inverted) {
  const double* g = block(t.sample_gradients, b, 12);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) {
      double value[L];
      for (int l = 0; l < L; ++l) value[l] = i == k ? 1.0 : 0.0;
      for (int a = 0; a < 4; ++a)
        for (int l = 0; l < L; ++l) value[l] = fused(u(3 * a + i, l), g[(3 * a + k) * L + l], value[l]);
      for (int l = 0; l < L; ++l) f(3 * k + i, l) = value[l];
    }
  int inverted = 0;
  for (int l = 0; l < L; ++l) {
    const double det = f(0, l) * (f(4, l) * f(8, l) - f(7, l) * f(5, l)) -
                       f(3, l) * (f(1, l) * f(8, l) - f(7, l) * f(2, l)) +
                       f(6, l) * (f(1, l) * f(5, l) - f(4, l) * f(2, l));
    const bool positive = det > 0.0;
    f(9, l) = positive ? 1.0 : 0.0;
    inverted += positive ? 0 : 1;
  }
  if (identity_when_inverted)
    for (int k = 0; k < 9; ++k)
      for (int l = 0; l < L; ++l) f(k, l) = f(9, l) > 0.0 ? f(k, l) : (k % 4 == 0 ? 1.0 : 0.0);
  return inverted;
}

/// out = G^T (G x) per lane (G 6 x 12 of block g): both products summed in order.
void root_stiffness_product(const double* g, const double (*x)[L], double (*out)[L]) {
  double strain[6][L] = {};  // the 6 sums side by side, each over k in order
  for (int k = 0; k < 12; ++k)
#pragma GCC unroll 6
    for (int i = 0; i < 6; ++i)
      for (int l = 0; l < L; ++l) strain[i][l] = fused(g[(12 * i + k) * L + l], x[k][l], strain[i][l]);
  double sums[12][L] = {};  // the 12 sums side by side, each over i in order
  for (int i = 0; i < 6; ++i)
#pragma GCC unroll 12
    for (int k = 0; k < 12; ++k)
      for (int l = 0; l < L; ++l) sums[k][l] = fused(g[(12 * i + k) * L + l], strain[i][l], sums[k][l]);
  for (int k = 0; k < 12; ++k)
    for (int l = 0; l < L; ++l) out[k][l] = sums[k][l];
}

/// f += G^T G u per lane: the sample's linear force taken back out (the remainder).
void add_rest_force(const double* g, const Lanes& u, double (*f)[L]) {
  double x[12][L], back[12][L];
  for (int k = 0; k < 12; ++k)
    for (int l = 0; l < L; ++l) x[k][l] = u(k, l);
  root_stiffness_product(g, x, back);
  for (int k = 0; k < 12; ++k)
    for (int l = 0; l < L; ++l) f[k][l] += back[k][l];
}

/// The lanes' corotational forces f = -R G^T G (R^T x - X) at displacements u.
void corotational_block_forces(const CubatureView& t, int b, const Lanes& u, const Lanes& rot, double (*f)[L]) {
  const double* rest = block(t.sample_rest_m, b, 12);
  const double* g = block(t.sample_root_stiffness, b, 72);
  auto rotation = [&rot](int i, int j, int l) { return rot(3 * j + i, l); };
  double local[12][L];
  for (int a = 0; a < 4; ++a)
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < L; ++l) {
        const double x0 = rest[(3 * a) * L + l] + u(3 * a, l);
        const double x1 = rest[(3 * a + 1) * L + l] + u(3 * a + 1, l);
        const double x2 = rest[(3 * a + 2) * L + l] + u(3 * a + 2, l);
        local[3 * a + k][l] = fused(rotation(2, k, l), x2, fused(rotation(1, k, l), x1, rotation(0, k, l) * x0)) -
                              rest[(3 * a + k) * L + l];
      }
  double back[12][L];
  root_stiffness_product(g, local, back);
  for (int a = 0; a < 4; ++a)
    for (int c = 0; c < 3; ++c)
      for (int l = 0; l < L; ++l)
        f[3 * a + c][l] = -fused(rotation(c, 2, l), back[3 * a + 2][l],
                                 fused(rotation(c, 1, l), back[3 * a + 1][l], rotation(c, 0, l) * back[3 * a][l]));
}

double* forces_of(const CubatureView& t, const SampleWork& work, int b) {
  return work.per_block ? work.lane_forces + index(b) * index(t.r) * L : work.lane_forces;
}

/// x^(1/4) of a positive finite x to about 1e-3: the exponent quartered in the bit pattern
/// (within 20 %), then one Newton step on y^4 = x.
double quartic_root(double x) {
  const double y = __builtin_bit_cast(double, (__builtin_bit_cast(unsigned long long, x) >> 2) + 0x2FF4000000000000ull);
  return 0.75 * y + 0.25 * x / (y * y * y);
}

/// Matrices iterated together by polar_range, in local arrays: entry (i, j) of matrix n at [3 j + i][n].
constexpr Index kChunk = 16;
using PolarChunk = double[9][kChunk];

/// One scaled Newton iteration of the polar decomposition on every matrix of x, in place; with
/// kTrack, each matrix's largest entry change into `change`.
template <bool kTrack>
void polar_iteration(PolarChunk& x, double (&change)[kChunk]) {
  for (Index n = 0; n < kChunk; ++n) {
    double c[9];  // cofactors (det R R^-T), same layout
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        c[3 * j + i] = fused(x[3 * j1 + i1][n], x[3 * j2 + i2][n], -(x[3 * j2 + i1][n] * x[3 * j1 + i2][n]));
      }
    const double det = fused(x[6][n], c[6], fused(x[3][n], c[3], x[0][n] * c[0]));
    double norm_x = 0.0, norm_c = 0.0;
    for (int k = 0; k < 9; ++k) {
      norm_x += x[k][n] * x[k][n];
      norm_c += c[k] * c[k];
    }
    // g^4 = |R^-T|^2 / |R|^2 = |cofactors|^2 / (det^2 |R|^2); R <- (g R + cofactors / (g det)) / 2.
    const double scale = quartic_root(norm_c / (det * det * norm_x));
    const double own = 0.5 * scale, inverse = 0.5 / (scale * det);
    double largest = 0.0;
    for (int k = 0; k < 9; ++k) {
      const double next = own * x[k][n] + inverse * c[k];
      if constexpr (kTrack) {
        const double difference = next - x[k][n];
        const double size = difference < 0.0 ? -difference : difference;
        largest = size > largest ? size : largest;
      }
      x[k][n] = next;
    }
    if constexpr (kTrack) change[n] = largest;
  }
}

/// Polar rotations of the `count` matrices from `first` of a k-major table with `stride` lanes:
/// kPolarFirstIterations each, then each until it converged or kPolarIterations.
void polar_range(double* a, Index stride, Index first_lane, Index count) {
  for (Index first = first_lane; first < first_lane + count; first += kChunk) {
    const Index width = first_lane + count - first < kChunk ? first_lane + count - first : kChunk;
    PolarChunk x;  // the lanes past width hold the identity
    for (Index k = 0; k < 9; ++k)
      for (Index n = 0; n < kChunk; ++n) x[k][n] = n < width ? a[k * stride + first + n] : (k % 4 == 0 ? 1.0 : 0.0);
    double change[kChunk];
    for (int iteration = 1; iteration < kPolarFirstIterations; ++iteration) polar_iteration<false>(x, change);
    polar_iteration<true>(x, change);
    // The rare matrices not converged yet go on alone: the others are put back after each iteration.
    double converged[kChunk], left = 0.0;
    for (Index n = 0; n < kChunk; ++n) {
      converged[n] = change[n] <= kPolarConvergedChange ? 1.0 : 0.0;
      left += 1.0 - converged[n];
    }
    for (int iteration = kPolarFirstIterations; iteration < kPolarIterations && left > 0.0; ++iteration) {
      PolarChunk before;
      for (int k = 0; k < 9; ++k)
        for (Index n = 0; n < kChunk; ++n) before[k][n] = x[k][n];
      polar_iteration<true>(x, change);
      left = 0.0;
      for (Index n = 0; n < kChunk; ++n) {
        for (int k = 0; k < 9; ++k) x[k][n] = converged[n] > 0.0 ? before[k][n] : x[k][n];
        converged[n] = converged[n] > 0.0 || change[n] <= kPolarConvergedChange ? 1.0 : 0.0;
        left += 1.0 - converged[n];
      }
    }
    for (Index k = 0; k < 9; ++k)
      if (width == kChunk)  // a fixed count: moved as whole vectors, not as a string copy
        for (Index n = 0; n < kChunk; ++n) a[k * stride + first + n] = x[k][n];
      else
        for (Index n = 0; n < width; ++n) a[k * stride + first + n] = x[k][n];
  }
}

void polar_rotations(double* a, Index lanes) noexcept { polar_range(a, lanes, 0, lanes); }

NAV_LANES_NOT_LOOP void panel_times(const double* panels, const double* lift_panels, const double* q, int r,
                                    const double* prescribed_m, double* out, Index values) noexcept {
  constexpr Index P = 2;  // panels at a time: independent sums to overlap
  const Index panel_count = (values + L - 1) / L;
  for (Index panel = 0; panel < panel_count; panel += P) {
    const Index together = panel_count - panel < P ? panel_count - panel : P;
    double acc[P][L] = {};
    const double* p = panels + panel * index(r) * L;
    if (together == P) {
      for (int j = 0; j < r; ++j)
        for (Index k = 0; k < P; ++k)
          for (int l = 0; l < L; ++l) acc[k][l] += p[(k * index(r) + index(j)) * L + l] * q[j];
    } else {
      for (int j = 0; j < r; ++j)
        for (int l = 0; l < L; ++l) acc[0][l] += p[j * L + l] * q[j];
    }
    for (Index k = 0; k < together; ++k) {
      if (lift_panels != nullptr) {
        const double* lift = lift_panels + (panel + k) * 3 * L;
        for (int c = 0; c < 3; ++c)
          for (int l = 0; l < L; ++l) acc[k][l] += lift[c * L + l] * prescribed_m[c];
      }
      const Index first = (panel + k) * L, width = values - first < L ? values - first : L;
      for (Index l = 0; l < width; ++l) out[first + l] = acc[k][l];
    }
  }
}

/// Blocks whose gathers, rotations, forces and scatters run together: their basis rows stay
/// in the first-level cache from the gather to the scatter, and their rotations make one
/// chunk of polar_range (independent chains that overlap each other's latency).
constexpr int kBlocksTogether = 2;

int corotational_forces(const CubatureView& t, const LaneState& state, bool remainder,
                        const SampleWork& work) noexcept {
  const Index lanes = lane_count(t);
  int inverted = 0;
  for (int first = 0; first < t.sample_blocks; first += kBlocksTogether) {
    const int end = first + kBlocksTogether < t.sample_blocks ? first + kBlocksTogether : t.sample_blocks;
    for (int b = first; b < end; ++b) {
      const Lanes u = lanes_of(work.displacements, t, b);
      gather(t, b, state, u);
      inverted += deformation(t, b, u, lanes_of(work.gradients, t, b), true);
    }
    const Index first_lane = index(first) * L, count = index(end - first) * L;
    polar_range(work.gradients, lanes, first_lane, count);
    const double* positive = work.gradients + 9 * lanes;
    for (Index k = 0; k < 9; ++k)
      for (Index n = first_lane; n < first_lane + count; ++n)
        work.rotations[k * lanes + n] =
            positive[n] > 0.0 ? work.gradients[k * lanes + n] : work.rotations[k * lanes + n];
    for (int b = first; b < end; ++b) {
      const Lanes u = lanes_of(work.displacements, t, b);
      double f[12][L];
      corotational_block_forces(t, b, u, lanes_of(work.rotations, t, b), f);
      if (remainder) add_rest_force(block(t.sample_root_stiffness, b, 72), u, f);
      scatter(t, b, f, forces_of(t, work, b));
    }
  }
  return inverted;
}

int deformations(const CubatureView& t, const LaneState& state, const SampleWork& work) noexcept {
  int inverted = 0;
  for (int b = 0; b < t.sample_blocks; ++b) {
    const Lanes u = lanes_of(work.displacements, t, b);
    gather(t, b, state, u);
    inverted += deformation(t, b, u, lanes_of(work.gradients, t, b), false);
  }
  return inverted;
}

void add_block_forces(const CubatureView& t, int b, bool remainder, const LaneForces& forces,
                      const SampleWork& work) noexcept {
  double f[12][L];
  for (int k = 0; k < 12; ++k)
    for (int l = 0; l < L; ++l) f[k][l] = forces[k][l];
  if (remainder) add_rest_force(block(t.sample_root_stiffness, b, 72), lanes_of(work.displacements, t, b), f);
  scatter(t, b, f, forces_of(t, work, b));
}

void add_corotational_tangent_block(const CubatureView& t, int b, const SampleWork& work, double* rows_work,
                                    double* tangent) noexcept {
  const int r = t.r, stride = padded(r);
  const double* rows = block(t.sample_rows, b, 12 * r);
  const double* g = block(t.sample_root_stiffness, b, 72);
  const Lanes rot = lanes_of(work.rotations, t, b);
  // H = G blockdiag(R^T): H(i, 3a + k) = sum_c G(i, 3a + c) R(k, c), per lane.
  double h[72][L];
  for (int i = 0; i < 6; ++i)
    for (int a = 0; a < 4; ++a)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < L; ++l)
          h[12 * i + 3 * a + k][l] =
              fused(g[(12 * i + 3 * a + 2) * L + l], rot(6 + k, l),
                    fused(g[(12 * i + 3 * a + 1) * L + l], rot(3 + k, l), g[(12 * i + 3 * a) * L + l] * rot(k, l)));
  // V = H U_s, stored as W (6 L x stride): row p = L i + l holds lane l's row i of V.
  double* w = rows_work;
  for (int i = 0; i < 6; ++i)
    for_basis_sums(rows, r, h + 12 * i, [&](int j0, int width, const double(&sums)[kColumnsTogether][L]) {
      for (int j = 0; j < width; ++j)
        for (int l = 0; l < L; ++l) w[index((L * i + l) * stride + j0 + j)] = sums[j][l];
    });
  for (int p = 0; p < 6 * L; ++p)
    for (int j = r; j < stride; ++j) w[index(p * stride + j)] = 0.0;
  // tangent += W^T W on the tiles at or right of the diagonal, two rows at a time; each entry
  // sums over p in order.
  constexpr int kTile = kTangentTile;
  for (int j1 = 0; j1 < r; j1 += 2) {
    const bool second = j1 + 1 < r;
    for (int t0 = j1 / kTile * kTile; t0 < r; t0 += kTile) {
      const int width = r - t0 < kTile ? r - t0 : kTile;
      double acc0[kTile] = {}, acc1[kTile] = {};
      for (int p = 0; p < 6 * L; ++p) {
        const double* wp = w + index(p * stride);
        const double w0 = wp[j1], w1 = wp[j1 + 1];
        double tile[kTile];
        for (int c = 0; c < kTile; ++c) tile[c] = wp[t0 + c];
        for (int c = 0; c < kTile; ++c) acc0[c] = fused(w0, tile[c], acc0[c]);
        for (int c = 0; c < kTile; ++c) acc1[c] = fused(w1, tile[c], acc1[c]);
      }
      double* out0 = tangent + index(j1 * r + t0);
      for (int c = 0; c < width; ++c) out0[c] += acc0[c];
      if (!second) continue;
      double* out1 = out0 + r;
      for (int c = 0; c < width; ++c) out1[c] += acc1[c];
    }
  }
}

}  // namespace
}  // namespace nav::detail::NAV_KERNEL_ISA_NAMESPACE

namespace nav::detail {

extern const ReducedLaneKernels NAV_KERNEL_ISA_NAME(reduced_lane_kernels_);
const ReducedLaneKernels NAV_KERNEL_ISA_NAME(reduced_lane_kernels_){
    NAV_KERNEL_ISA_NAMESPACE::corotational_forces, NAV_KERNEL_ISA_NAMESPACE::deformations,
    NAV_KERNEL_ISA_NAMESPACE::add_block_forces,    NAV_KERNEL_ISA_NAMESPACE::add_corotational_tangent_block,
    NAV_KERNEL_ISA_NAMESPACE::polar_rotations,     NAV_KERNEL_ISA_NAMESPACE::panel_times,
};

}  // namespace nav::detail
