// The lane kernels of the needle-tissue solver, compiled once per instruction set (see
// nav/core/kernel_isa_variant.hpp): projected Gauss-Seidel whose gap updates are plain loops
// over independent rows, and the row combinations of the compliance assembly, whose loops run
// over independent values, and the nearest-node scan, whose distances and comparisons run over
// independent lanes; the compiler vectorizes them to the variant's width, and every sum
// runs in an order written here, so every variant gives the same bits. The transpositions
// between the products move 8 x 8 blocks through registers with shuffles (GCC vector
// extensions, lowered to each variant's own; copies, so the same bits too).
#include "nav/needle/needle_lane_kernels.hpp"
#include "nav/core/kernel_isa_variant.hpp"

namespace nav::detail::NAV_KERNEL_ISA_NAMESPACE {
namespace {

using Index = std::size_t;

/// clamp(v, lo, hi) with the comparisons of the standard library's.
double clamped(double v, double lo, double hi) {
  const double above = v < lo ? lo : v;
  return hi < above ? hi : above;
}

/// gaps += column change (nothing when change is zero: a force held at its bound).
void add_column(const double* __restrict column, Index m, double change, double* __restrict gaps) {
  if (change == 0.0) return;
  for (Index i = 0; i < m; ++i) gaps[i] += column[i] * change;
}

/// gaps += W[:, first:first + size] change, in one pass over the gaps for a full point.
void add_columns(const double* w, Index m, Index stride, Index first, Index size, const double* change,
                 double* __restrict gaps) {
  const double* __restrict a = w + first * stride;
  if (size == 3) {
    const double* __restrict b = a + stride;
    const double* __restrict c = b + stride;
    const double c0 = change[0], c1 = change[1], c2 = change[2];
    for (Index i = 0; i < m; ++i) gaps[i] += (a[i] * c0 + b[i] * c1) + c[i] * c2;
    return;
  }
  for (Index j = 0; j < size; ++j) add_column(a + j * stride, m, change[j], gaps);
}

/// One sweep's work on the constraint point of rows [first, first + Size). Size is a
/// constant so that the point's block, changes and gaps stay in registers: the chain from one
/// row's projection to the next row's gap never goes through memory.
template <Index Size>
void solve_point(const SweepProblem& p, Index first) {
  const Index stride = p.w_stride;
  double* forces = p.forces;
  double block[Size][Size] = {}, inverse_diagonal[Size] = {}, change[Size] = {};
#pragma GCC unroll 3
  for (Index i = 0; i < Size; ++i) {
#pragma GCC unroll 3
    for (Index j = 0; j < Size; ++j) block[i][j] = p.w[(first + j) * stride + first + i];
    inverse_diagonal[i] = p.rows[first + i].inverse_diagonal;
  }
  // Row i's gap is gaps + sum_j block[i][j] change[j], j in order, where the changes of the
  // rows not yet solved (j >= `from`, never past the last) are still +0. Their terms are zeros (NaN from a
  // non-finite W), for which ((g + z) + z') = g + (z + z') bit for bit: they are summed
  // apart, off the chain that runs from one row's projection to the next row's gap.
  const auto unchanged_terms = [&](Index i, Index from) {
    double z = block[i][from] * change[from];
#pragma GCC unroll 3
    for (Index j = from + 1; j < Size; ++j) z += block[i][j] * change[j];
    return z;
  };
  // g + z is g itself, bit for bit, when z is a zero and g is not (x + 0 = x for x != 0):
  // the usual case, predicted, so that the add leaves the chain.
  const auto gap_now = [&](Index i, Index from) {
    double g = p.gaps[first + i];
#pragma GCC unroll 3
    for (Index j = 0; j < from; ++j) g += block[i][j] * change[j];
    const double z = unchanged_terms(i, from);
    if (__builtin_expect(z == 0.0 && g != 0.0, 1)) return g;
    return g + z;
  };
#pragma GCC unroll 3
  for (Index i = 0; i < Size; ++i) {
    const Index r = first + i;
    const SweepRow& row = p.rows[r];
    if (row.law == RowLaw::coulomb_second || inverse_diagonal[i] == 0.0) continue;
    if (row.law == RowLaw::coulomb_pair && i + 1 < Size) {
      // Both tangent rows, then back onto the disk of radius mu * normal force.
      double f1 = forces[r] - gap_now(i, i) * inverse_diagonal[i],
             f2 = forces[r + 1] - gap_now(i + 1, i) * inverse_diagonal[i + 1];
      const double limit = row_force_limit_n(row, forces), length = __builtin_sqrt(f1 * f1 + f2 * f2);
      if (length > limit) {
        f1 *= limit / length;
        f2 *= limit / length;
      }
      change[i] += f1 - forces[r];
      change[i + 1] += f2 - forces[r + 1];
      forces[r] = f1;
      forces[r + 1] = f2;
      continue;
    }
    double f = forces[r] - gap_now(i, i) * inverse_diagonal[i];
    if (row.law == RowLaw::unilateral_capped) f = clamped(f, 0.0, row.cap);
    if (row.law == RowLaw::friction_axial) {
      const double limit = row_force_limit_n(row, forces);
      f = clamped(f, -limit, limit);
    }
    change[i] += f - forces[r];
    forces[r] = f;
  }
  add_columns(p.w, p.m, stride, first, Size, change, p.gaps);
}

void gauss_seidel(const SweepProblem& p, int sweeps) noexcept {
  const Index m = p.m;
  for (Index j = 0; j < m; ++j) add_column(p.w + j * p.w_stride, m, p.forces[j], p.gaps);
  if (m == 0) return;
  for (int sweep = 0; sweep < sweeps; ++sweep)
    for (std::int32_t first = 0; first >= 0; first = p.rows[first].next_point) {
      switch (p.rows[first].point_rows) {
        case 3:
          solve_point<3>(p, static_cast<Index>(first));
          break;
        case 2:
          solve_point<2>(p, static_cast<Index>(first));
          break;
        default:
          solve_point<1>(p, static_cast<Index>(first));
          break;
      }
    }
}

/// out = sum_k c_k rows_k over `width` values, k in order (at least one term): one
/// independent chain per value, so the loop over values runs as wide as the variant allows.
/// Terms is 0 for a count known only at run time.
template <Index Terms>
void combine_row(const double* c, const double* const* rows, Index terms, Index width, double* __restrict out) {
  const Index count = Terms > 0 ? Terms : terms;
  for (Index i = 0; i < width; ++i) {
    double v = c[0] * rows[0][i];
#pragma GCC unroll 9
    for (Index k = 1; k < count; ++k) v += c[k] * rows[k][i];
    out[i] = v;
  }
}

void combine_rows(const RowCombination& p) noexcept {
  const double* rows[kMaxCombinedTerms] = {};
  for (Index r = 0; r < p.rows; ++r) {
    const double* c = p.coefficients + r * p.term_stride;
    for (Index k = 0; k < p.terms; ++k)
      rows[k] = p.dense + static_cast<Index>(p.sources[r * p.term_stride + k]) * p.dense_stride;
    const Index lanes = kCombinedLanes, triangle = (r + lanes) / lanes * lanes;  // r + 1 rounded up
    const Index width = p.lower_triangle && triangle < p.width ? triangle : p.width;
    double* out = p.out + r * p.out_stride;
    switch (p.terms) {
      case 3:
        combine_row<3>(c, rows, 3, width, out);
        break;
      case 6:
        combine_row<6>(c, rows, 6, width, out);
        break;
      case 9:
        combine_row<9>(c, rows, 9, width, out);
        break;
      default:
        combine_row<0>(c, rows, p.terms, width, out);
        break;
    }
  }
}

/// Eight doubles as one value: an 8 x 8 block's row, which shuffles rearrange in registers.
using Eight = double __attribute__((vector_size(64)));

/// The 8 x 8 block at src (rows src_stride apart) transposed to dst (rows dst_stride apart):
/// pairs of rows interleaved, then pairs of pairs, then halves.
void transpose_8x8(const double* __restrict src, Index src_stride, double* __restrict dst, Index dst_stride) {
  Eight row[8], pair[8], quad[8];
#pragma GCC unroll 8
  for (Index i = 0; i < 8; ++i) __builtin_memcpy(&row[i], src + i * src_stride, sizeof(Eight));
#pragma GCC unroll 4
  for (Index i = 0; i < 8; i += 2) {
    pair[i] = __builtin_shufflevector(row[i], row[i + 1], 0, 8, 2, 10, 4, 12, 6, 14);
    pair[i + 1] = __builtin_shufflevector(row[i], row[i + 1], 1, 9, 3, 11, 5, 13, 7, 15);
  }
#pragma GCC unroll 2
  for (Index i = 0; i < 8; i += 4)
#pragma GCC unroll 2
    for (Index j = 0; j < 2; ++j) {
      quad[i + j] = __builtin_shufflevector(pair[i + j], pair[i + j + 2], 0, 1, 8, 9, 4, 5, 12, 13);
      quad[i + j + 2] = __builtin_shufflevector(pair[i + j], pair[i + j + 2], 2, 3, 10, 11, 6, 7, 14, 15);
    }
#pragma GCC unroll 4
  for (Index j = 0; j < 4; ++j) {
    const Eight low = __builtin_shufflevector(quad[j], quad[j + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    const Eight high = __builtin_shufflevector(quad[j], quad[j + 4], 4, 5, 6, 7, 12, 13, 14, 15);
    __builtin_memcpy(dst + j * dst_stride, &low, sizeof(Eight));
    __builtin_memcpy(dst + (j + 4) * dst_stride, &high, sizeof(Eight));
  }
}

/// Rows [row_begin, row_end) by columns [col_begin, col_end) of a Transposition, one value at a time.
void transpose_values(const Transposition& t, Index row_begin, Index row_end, Index col_begin, Index col_end) {
  for (Index c = col_begin; c < col_end; ++c)
    for (Index r = row_begin; r < row_end; ++r) t.dst[c * t.dst_stride + r] = t.src[r * t.src_stride + c];
}

void transpose(const Transposition& t) noexcept {
  const Index whole_rows = t.rows / 8 * 8, whole_cols = t.cols / 8 * 8;
  for (Index r = 0; r < whole_rows; r += 8)
    for (Index c = 0; c < whole_cols; c += 8)
      transpose_8x8(t.src + r * t.src_stride + c, t.src_stride, t.dst + c * t.dst_stride + r, t.dst_stride);
  transpose_values(t, 0, whole_rows, whole_cols, t.cols);
  transpose_values(t, whole_rows, t.rows, 0, t.cols);
}

void mirror_lower(double* a, Index n, Index stride) noexcept {
  for (Index s = 0; s < n; s += 8) {
    // Band [s, end): its diagonal block's upper part, the whole blocks below it, the rest.
    const Index end = s + 8 < n ? s + 8 : n;
    for (Index i = s; i < end; ++i)
      for (Index r = i + 1; r < end; ++r) a[i * stride + r] = a[r * stride + i];
    Index r = end;
    if (end - s == 8)
      for (; r + 8 <= n; r += 8) transpose_8x8(a + r * stride + s, stride, a + s * stride + r, stride);
    for (Index i = s; i < end; ++i)
      for (Index k = r; k < n; ++k) a[i * stride + k] = a[k * stride + i];
  }
}

/// Squared distance of node n from the query's point, summed x, y, then z.
template <bool Displaced>
[[gnu::always_inline]] inline double squared_distance(const double* __restrict rest, const double* __restrict u,
                                                      Index n, double px, double py, double pz) {
  double x = rest[3 * n], y = rest[3 * n + 1], z = rest[3 * n + 2];
  if constexpr (Displaced) {
    x += u[3 * n];
    y += u[3 * n + 1];
    z += u[3 * n + 2];
  }
  const double dx = x - px, dy = y - py, dz = z - pz;
  return (dx * dx + dy * dy) + dz * dz;
}

/// Lane `lane`'s best becomes node n when n is strictly nearer (a NaN distance never is).
[[gnu::always_inline]] inline void keep_nearer(double d2, Index n, Index lane, double* __restrict best,
                                               std::int64_t* __restrict index) {
  const bool nearer = d2 < best[lane];
  best[lane] = nearer ? d2 : best[lane];
  index[lane] = nearer ? static_cast<std::int64_t>(n) : index[lane];
}

/// Nodes [begin, end) into the lanes' bests, node begin + k in lane k % kCombinedLanes, each
/// lane keeping the first of its strictly nearest: the distances of a block of nodes and
/// their comparisons run across the lanes.
template <bool Displaced>
void scan_nodes(const NearestNodeQuery& q, Index begin, Index end, double* __restrict best,
                std::int64_t* __restrict index) {
  constexpr Index lanes = kCombinedLanes;
  const double px = q.point_m[0], py = q.point_m[1], pz = q.point_m[2];
  Index n = begin;
  for (; n + lanes <= end; n += lanes)
    for (Index l = 0; l < lanes; ++l)
      keep_nearer(squared_distance<Displaced>(q.rest_m, q.displacements_m, n + l, px, py, pz), n + l, l, best, index);
  for (Index l = 0; n + l < end; ++l)
    keep_nearer(squared_distance<Displaced>(q.rest_m, q.displacements_m, n + l, px, py, pz), n + l, l, best, index);
}

std::int32_t nearest_node(const NearestNodeQuery& q) noexcept {
  if (q.nodes == 0) return -1;
  double best[kCombinedLanes];
  std::int64_t index[kCombinedLanes];
  for (Index l = 0; l < kCombinedLanes; ++l) {
    best[l] = __builtin_inf();
    index[l] = -1;
  }
  const Index displaced_end = q.displaced > 1 ? q.displaced : 1;
  scan_nodes<true>(q, 1, displaced_end, best, index);
  scan_nodes<false>(q, displaced_end, q.nodes, best, index);
  // The lanes' bests against node 0: the nearest, the first of equals.
  const double* p = q.point_m;
  double nearest_d2 = q.displaced > 0 ? squared_distance<true>(q.rest_m, q.displacements_m, 0, p[0], p[1], p[2])
                                      : squared_distance<false>(q.rest_m, q.displacements_m, 0, p[0], p[1], p[2]);
  std::int64_t nearest = 0;
  for (Index l = 0; l < kCombinedLanes; ++l)
    if (index[l] >= 0 && (best[l] < nearest_d2 || (best[l] == nearest_d2 && index[l] < nearest))) {
      nearest_d2 = best[l];
      nearest = index[l];
    }
  return static_cast<std::int32_t>(nearest);
}

}  // namespace
}  // namespace nav::detail::NAV_KERNEL_ISA_NAMESPACE

namespace nav::detail {

extern const NeedleLaneKernels NAV_KERNEL_ISA_NAME(needle_lane_kernels_);
const NeedleLaneKernels NAV_KERNEL_ISA_NAME(needle_lane_kernels_){
    NAV_KERNEL_ISA_NAMESPACE::gauss_seidel, NAV_KERNEL_ISA_NAMESPACE::combine_rows,
    NAV_KERNEL_ISA_NAMESPACE::nearest_node, NAV_KERNEL_ISA_NAMESPACE::transpose,
    NAV_KERNEL_ISA_NAMESPACE::mirror_lower,
};

}  // namespace nav::detail
