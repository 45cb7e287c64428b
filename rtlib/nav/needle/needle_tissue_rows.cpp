#include "nav/needle/needle_tissue_rows.hpp"

#include <algorithm>
#include <cmath>

#include "nav/needle/needle_step.hpp"
#include "nav/needle/tissue_points.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav::detail {

namespace {

Eigen::Vector3d vec(const Point3& p) { return Eigen::Vector3d(p[0], p[1], p[2]); }

/// Two unit vectors completing `axis` to an orthonormal frame, the first taken from `hint`.
void complete_frame(const Eigen::Vector3d& axis, const Eigen::Vector3d& hint, Eigen::Vector3d& first,
                    Eigen::Vector3d& second) {
  first = (hint - hint.dot(axis) * axis).normalized();
  second = axis.cross(first);
}

/// Appends one row and returns its index.
int add_row(NeedleTissueData& data, RowLaw law, int slot, int node, double weight, const Eigen::Vector3d& direction,
            const Eigen::Vector3d& needle_point_m, const Eigen::Vector3d& tissue_point_m, std::int32_t tissue_node,
            double cap, double mu) {
  ConstraintRow& row = data.rows[static_cast<std::size_t>(data.row_count)];
  row.law = law;
  row.slot = slot;
  row.node = node;
  row.weight = weight;
  row.direction = direction;
  row.tissue_point_m = tissue_point_m;
  row.tissue_node = tissue_node;
  row.gap_free_m = direction.dot(needle_point_m - tissue_point_m);
  row.cap = cap;
  row.friction_coefficient = mu;
  row.linked[0] = row.linked[1] = -1;
  data.row_forces[static_cast<std::size_t>(data.row_count)] = data.slot_forces[static_cast<std::size_t>(slot)];
  return data.row_count++;
}

void add_contact_rows(const NeedleTissueModel& model, NeedleTissueData& data, int layer,
                      std::span<const double> displacements_m) {
  const TissueLayer& spec = model.scene.layers[static_cast<std::size_t>(layer)];
  const int tip_node = model.needle.element_count, slot = 3 * layer;
  const Eigen::Vector3d tip = needle_tip_m(data.needle);
  const Eigen::Vector3d contact =
      tissue_point_position_m(data.layers[static_cast<std::size_t>(layer)].contact, displacements_m);
  const Eigen::Vector3d n = data.layers[static_cast<std::size_t>(layer)].contact_normal;
  Eigen::Vector3d t1, t2;
  complete_frame(n, std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY(), t1, t2);
  const std::int32_t node = data.layers[static_cast<std::size_t>(layer)].contact.node;
  const int normal =
      add_row(data, RowLaw::unilateral_capped, slot, tip_node, 0.0, n, tip, contact, node, spec.puncture_force_n, 0.0);
  const int first = add_row(data, RowLaw::coulomb_pair, slot + 1, tip_node, 0.0, t1, tip, contact, node, 0.0,
                            spec.surface_friction_coefficient);
  const int second = add_row(data, RowLaw::coulomb_second, slot + 2, tip_node, 0.0, t2, tip, contact, node, 0.0,
                             spec.surface_friction_coefficient);
  data.rows[static_cast<std::size_t>(first)].linked[0] = normal;
  data.rows[static_cast<std::size_t>(second)].linked[0] = normal;
}

void add_tip_row(const NeedleTissueModel& model, NeedleTissueData& data, int layer,
                 std::span<const double> displacements_m) {
  const int tip_node = model.needle.element_count;
  const Eigen::Vector3d d = needle_tip_direction(data.needle), tip = needle_tip_m(data.needle);
  const TissuePoint& front = data.layers[static_cast<std::size_t>(layer)].cut_front;
  add_row(data, RowLaw::unilateral_capped, model.tip_slot(), tip_node, 0.0, -d, tip,
          tissue_point_position_m(front, displacements_m), front.node,
          model.scene.layers[static_cast<std::size_t>(layer)].cutting_force_n, 0.0);
}

void add_path_rows(const NeedleTissueModel& model, NeedleTissueData& data, int point,
                   std::span<const double> displacements_m) {
  const PathPoint& path = data.path[static_cast<std::size_t>(point)];
  const NeedleFrameAt at = needle_frame_at(model.needle, data.needle, path.arclength_m);
  const Eigen::Vector3d tissue = tissue_point_position_m(path.tissue, displacements_m);
  const int slot = model.path_slot(point);
  const TissueLayer& layer = model.scene.layers[static_cast<std::size_t>(path.layer)];
  const std::int32_t node = path.tissue.node;
  const int first =
      add_row(data, RowLaw::bilateral, slot, at.node, at.weight, at.normal1, at.point_m, tissue, node, 0.0, 0.0);
  const int second =
      add_row(data, RowLaw::bilateral, slot + 1, at.node, at.weight, at.normal2, at.point_m, tissue, node, 0.0, 0.0);
  const int axial =
      add_row(data, RowLaw::friction_axial, slot + 2, at.node, at.weight, at.tangent, at.point_m, tissue, node,
              layer.friction_per_length_n_m * model.scene.path_spacing_m, model.scene.shaft_friction_coefficient);
  data.rows[static_cast<std::size_t>(axial)].linked[0] = first;
  data.rows[static_cast<std::size_t>(axial)].linked[1] = second;
}

/// Node `node`'s 3 x rank rows of the low-rank tissue compliance.
const double* node_factors(const NeedleTissueModel& model, std::int32_t node) {
  return model.compliance_factors.data() +
         3 * static_cast<std::size_t>(node) * static_cast<std::size_t>(model.compliance_rank);
}

double dot(const double* a, const double* b, int n) {
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += a[j] * b[j];
  return sum;
}

/// `count` rounded up to whole kCombinedLanes.
std::size_t padded(std::size_t count) { return (count + kCombinedLanes - 1) / kCombinedLanes * kCombinedLanes; }

/// The sum of force(r) along each row's direction over the rows on distinct tissue node k.
template <class ForceOfRow>
Eigen::Vector3d force_on_distinct_node(const NeedleTissueData& data, std::size_t k, ForceOfRow force) {
  Eigen::Vector3d on_node = Eigen::Vector3d::Zero();
  for (std::size_t p = 0; p < static_cast<std::size_t>(data.point_count); ++p) {
    if (static_cast<std::size_t>(data.point_tissue_index[p]) != k) continue;
    for (auto r = static_cast<std::size_t>(data.point_first_row[p]);
         r < static_cast<std::size_t>(data.point_first_row[p + 1]); ++r)
      on_node += force(r) * data.rows[r].direction;
  }
  return on_node;
}

/// Full order: the cache slot of node `node`'s responses, solved now (three solves with the
/// tissue's rest factor) into the least recently used slot when no slot holds them. The slots
/// of this step's nodes are never the least recently used: the cache outnumbers them.
std::size_t response_slot(const NeedleTissueModel& model, NeedleTissueData& data, std::int32_t node) {
  std::size_t chosen = 0;
  for (std::size_t s = 0; s < data.response_nodes.size(); ++s) {
    if (data.response_nodes[s] == node) {
      data.response_used[s] = data.steps;
      return s;
    }
    if (data.response_used[s] < data.response_used[chosen]) chosen = s;
  }
  const std::size_t values = model.tissue_rest_m.size();
  for (int axis = 0; axis < 3; ++axis)
    rest_step_response_m(*model.node_response_source, node, axis,
                         data.responses_m_per_n.subspan((3 * chosen + static_cast<std::size_t>(axis)) * values, values),
                         data.response_work);
  data.response_nodes[chosen] = node;
  data.response_used[chosen] = data.steps;
  return chosen;
}

/// Full order: node `at`'s displacement per newton on the node of cache slot `slot` (3 x 3,
/// column j for a force along axis j).
Eigen::Matrix3d response_block(const NeedleTissueModel& model, const NeedleTissueData& data, std::int32_t slot,
                               std::int32_t at) {
  const std::size_t values = model.tissue_rest_m.size();
  Eigen::Matrix3d block;
  for (std::size_t j = 0; j < 3; ++j)
    for (std::size_t i = 0; i < 3; ++i)
      block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
          data.responses_m_per_n[(3 * static_cast<std::size_t>(slot) + j) * values + 3 * static_cast<std::size_t>(at) +
                                 i];
  return block;
}

/// Full order: the slots of the distinct tissue nodes (solved where missing) and the
/// tissue's compliance between them, laid out as tissue_node_compliance() does.
void full_order_node_compliance(const NeedleTissueModel& model, NeedleTissueData& data) {
  const auto distinct = static_cast<std::size_t>(data.distinct_tissue_node_count);
  for (std::size_t k = 0; k < distinct; ++k) {
    const std::int32_t node = data.distinct_tissue_nodes[k];
    data.distinct_response_slot[k] = node >= 0 ? static_cast<std::int32_t>(response_slot(model, data, node)) : -1;
  }
  const std::size_t stride = padded(3 * distinct);
  double* dense = data.low_rank.tissue_compliance.data();
  for (std::size_t k = 0; k < distinct; ++k)
    for (std::size_t l = 0; l <= k; ++l) {
      const std::int32_t at = data.distinct_tissue_nodes[k], slot = data.distinct_response_slot[l];
      const Eigen::Matrix3d block =
          at >= 0 && slot >= 0 ? response_block(model, data, slot, at) : Eigen::Matrix3d::Zero();
      for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j)
          dense[(3 * k + i) * stride + 3 * l + j] = dense[(3 * l + j) * stride + 3 * k + i] =
              block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
}

/// Full order: node `at`'s displacement under force(r) along each row's direction, on the
/// rows' distinct tissue nodes.
template <class ForceOfRow>
Eigen::Vector3d full_order_response(const NeedleTissueModel& model, const NeedleTissueData& data, ForceOfRow force,
                                    std::int32_t at) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  if (at < 0) return u;
  for (std::size_t k = 0; k < static_cast<std::size_t>(data.distinct_tissue_node_count); ++k) {
    const std::int32_t slot = data.distinct_response_slot[k];
    if (slot < 0) continue;
    const Eigen::Vector3d on_node = force_on_distinct_node(data, k, force);
    u += response_block(model, data, slot, at) * on_node;
  }
  return u;
}

/// Low rank: the tissue's compliance between the distinct tissue nodes, V_a V_b^T, laid out
/// as full_order_node_compliance() does.
void low_rank_node_compliance(const NeedleTissueModel& model, NeedleTissueData& data) {
  const int rank = model.compliance_rank;
  const auto distinct = static_cast<std::size_t>(data.distinct_tissue_node_count);
  const std::size_t stride = padded(3 * distinct);
  for (std::size_t k = 0; k < distinct; ++k)
    for (std::size_t l = 0; l <= k; ++l) {
      const std::int32_t a = data.distinct_tissue_nodes[k], b = data.distinct_tissue_nodes[l];
      // The nine sums over the rank side by side, each in order from zero.
      double sums[3][3] = {};
      if (a >= 0 && b >= 0) {
        const double* va = node_factors(model, a);
        const double* vb = node_factors(model, b);
        for (int n = 0; n < rank; ++n)
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) sums[i][j] += va[i * rank + n] * vb[j * rank + n];
      }
      double* dense = data.low_rank.tissue_compliance.data();
      for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j)
          dense[(3 * k + i) * stride + 3 * l + j] = dense[(3 * l + j) * stride + 3 * k + i] = sums[i][j];
    }
}

/// Adds the compliance the tissue model misses between the distinct tissue nodes
/// (model.missing_compliance, where it holds their pair) to the dense compliance between them.
void add_missing_compliance(const NeedleTissueModel& model, NeedleTissueData& data) {
  if (model.missing_compliance.starts.empty()) return;
  const auto distinct = static_cast<std::size_t>(data.distinct_tissue_node_count);
  const std::size_t stride = padded(3 * distinct);
  double* dense = data.low_rank.tissue_compliance.data();
  for (std::size_t k = 0; k < distinct; ++k)
    for (std::size_t l = 0; l <= k; ++l) {
      const double* block = model.missing_compliance.find(data.distinct_tissue_nodes[k], data.distinct_tissue_nodes[l]);
      if (block == nullptr) continue;
      for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j) {
          dense[(3 * k + i) * stride + 3 * l + j] += block[3 * i + j];
          if (l != k) dense[(3 * l + j) * stride + 3 * k + i] += block[3 * i + j];
        }
    }
}

/// The distinct tissue nodes of the constraint points (points on one node share them), each
/// point's index among those nodes, and the tissue's compliance between them (the full
/// order's responses or V_a V_b^T, and what the model misses), dense and row-major in
/// low_rank.tissue_compliance (padded(3 distinct) values per row).
void tissue_node_compliance(const NeedleTissueModel& model, NeedleTissueData& data) {
  const int rank = model.compliance_rank;
  std::size_t distinct = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(data.point_count); ++p) {
    const std::int32_t node = data.rows[static_cast<std::size_t>(data.point_first_row[p])].tissue_node;
    std::size_t k = 0;
    while (k < distinct && data.distinct_tissue_nodes[k] != node) ++k;
    if (k == distinct) data.distinct_tissue_nodes[distinct++] = node;
    data.point_tissue_index[p] = static_cast<std::int32_t>(k);
  }
  data.distinct_tissue_node_count = static_cast<int>(distinct);
  if (rank == 0)
    full_order_node_compliance(model, data);
  else
    low_rank_node_compliance(model, data);
  add_missing_compliance(model, data);
}

/// Low rank: sum_r c_r force(r) over the rows (c_r = V_node^T d_r), as sum over the distinct
/// tissue nodes k of V_k^T (sum of force(r) d_r over the rows on k), into `sum`
/// (compliance_rank values, zeroed first).
template <class ForceOfRow>
void factor_sum(const NeedleTissueModel& model, const NeedleTissueData& data, ForceOfRow force, double* sum) {
  const int rank = model.compliance_rank;
  std::fill_n(sum, rank, 0.0);
  for (std::size_t k = 0; k < static_cast<std::size_t>(data.distinct_tissue_node_count); ++k) {
    if (data.distinct_tissue_nodes[k] < 0) continue;
    const Eigen::Vector3d on_node = force_on_distinct_node(data, k, force);
    const double* v = node_factors(model, data.distinct_tissue_nodes[k]);
    for (int j = 0; j < rank; ++j)
      sum[j] += (v[j] * on_node.x() + v[rank + j] * on_node.y()) + v[2 * rank + j] * on_node.z();
  }
}

/// Low rank: takes the tissue's response to the forces it already carries out of the free
/// gaps through the rank-sized y = sum_s c_s applied_s: gap_r -= c_r . y = d_r . (V_node y),
/// O(m + r) per distinct node instead of one long chain of m^2 updates.
void remove_applied_response(const NeedleTissueModel& model, NeedleTissueData& data) {
  const int rank = model.compliance_rank;
  if (rank == 0) {  // full order
    const auto applied = [&](std::size_t r) {
      return data.applied_forces[static_cast<std::size_t>(data.rows[r].slot)];
    };
    for (std::size_t p = 0; p < static_cast<std::size_t>(data.point_count); ++p) {
      const std::int32_t node = data.distinct_tissue_nodes[static_cast<std::size_t>(data.point_tissue_index[p])];
      const Eigen::Vector3d response = full_order_response(model, data, applied, node);
      for (auto r = static_cast<std::size_t>(data.point_first_row[p]);
           r < static_cast<std::size_t>(data.point_first_row[p + 1]); ++r)
        data.rows[r].gap_free_m -= data.rows[r].direction.dot(response);
    }
    return;
  }
  double carried[kMaxComplianceRank];
  factor_sum(
      model, data, [&](std::size_t r) { return data.applied_forces[static_cast<std::size_t>(data.rows[r].slot)]; },
      carried);
  for (std::size_t p = 0; p < static_cast<std::size_t>(data.point_count); ++p) {
    const std::int32_t node = data.distinct_tissue_nodes[static_cast<std::size_t>(data.point_tissue_index[p])];
    if (node < 0) continue;
    const double* v = node_factors(model, node);
    const Eigen::Vector3d response(dot(v, carried, rank), dot(v + rank, carried, rank),
                                   dot(v + 2 * rank, carried, rank));
    for (auto r = static_cast<std::size_t>(data.point_first_row[p]);
         r < static_cast<std::size_t>(data.point_first_row[p + 1]); ++r)
      data.rows[r].gap_free_m -= data.rows[r].direction.dot(response);
  }
}

/// Low rank: row r's 9 entries of H, 3 for each of the needle nodes that carry its point
/// (weight times direction; a held or unused node gets zeros on `first_block`'s freedoms)
/// then its direction on its tissue node's freedoms, and their freedoms (needle ones from
/// `first_block`; in `sources` the tissue ones after `tissue_offset` needle ones).
void fill_row_entries(const NeedleTissueData& data, std::size_t r, std::size_t tissue_index, int first_block,
                      std::size_t tissue_offset) {
  const ConstraintRow& row = data.rows[r];
  const std::size_t at = kMaxCombinedTerms * r;
  double* c = data.low_rank.coefficients.data() + at;
  std::int32_t* local = data.low_rank.local_sources.data() + at;
  std::int32_t* combined = data.low_rank.sources.data() + at;
  for (int k = 0; k < 2; ++k) {
    const int node = row.node + k;
    const double w = k == 0 ? 1.0 - row.weight : row.weight;
    const bool used = node >= 1 && w != 0.0;
    const int freedom = 3 * ((used ? node - 1 : first_block) - first_block);
    for (int d = 0; d < 3; ++d) {
      c[3 * k + d] = used ? w * row.direction[d] : 0.0;
      local[3 * k + d] = combined[3 * k + d] = freedom + d;
    }
  }
  for (int d = 0; d < 3; ++d) {
    c[6 + d] = row.direction[d];
    local[6 + d] = static_cast<std::int32_t>(3 * tissue_index) + d;
    combined[6 + d] = static_cast<std::int32_t>(tissue_offset + 3 * tissue_index) + d;
  }
}

/// Low rank: W = H C H^T, C block-diagonal over the needle's translational freedoms from
/// `first_block` (its compliance A^-1, read in place) and the distinct tissue nodes' (V_a V_b^T), as
/// C H^T then H (C H^T) on the kernels (rows padded to whole lanes), lower triangle then
/// mirrored; plus on a point's own rows the local compliance the basis misses (never carried
/// by the tissue model, so not in the applied forces' response).
void assemble_low_rank(const NeedleTissueModel& model, NeedleTissueData& data, int first_block) {
  LowRankWorkspace& work = data.low_rank;
  const auto m = static_cast<std::size_t>(data.row_count), padded_m = padded(m);
  const auto blocks = static_cast<std::size_t>(data.needle.system.blocks);
  const std::size_t needle_nodes = blocks - static_cast<std::size_t>(first_block);
  const auto distinct = static_cast<std::size_t>(data.distinct_tissue_node_count);
  const std::size_t needle_freedoms = padded(3 * needle_nodes), tissue_freedoms = padded(3 * distinct);
  const std::size_t freedoms = needle_freedoms + tissue_freedoms;
  for (std::size_t p = 0; p < static_cast<std::size_t>(data.point_count); ++p)
    for (auto r = static_cast<std::size_t>(data.point_first_row[p]);
         r < static_cast<std::size_t>(data.point_first_row[p + 1]); ++r)
      fill_row_entries(data, r, static_cast<std::size_t>(data.point_tissue_index[p]), first_block, needle_freedoms);
  const NeedleLaneKernels& kernels = *model.lane_kernels;
  // C H^T, one row of fields per constraint row: its needle part, then its tissue part.
  kernels.combine_rows({m, 6, kMaxCombinedTerms, work.coefficients.data(), work.local_sources.data(),
                        needle_compliance_row(data.needle, first_block + 1), data.needle.translational_stride,
                        needle_freedoms, false, work.row_fields.data(), freedoms});
  kernels.combine_rows({m, 3, kMaxCombinedTerms, work.coefficients.data() + 6, work.local_sources.data() + 6,
                        work.tissue_compliance.data(), tissue_freedoms, tissue_freedoms, false,
                        work.row_fields.data() + needle_freedoms, freedoms});
  // Only the freedoms in use: no row of H names the padding.
  kernels.transpose({work.row_fields.data(), freedoms, m, 3 * needle_nodes, work.fields.data(), padded_m});
  kernels.transpose({work.row_fields.data() + needle_freedoms, freedoms, m, 3 * distinct,
                     work.fields.data() + needle_freedoms * padded_m, padded_m});
  const std::size_t stride = data.compliance_stride;
  kernels.combine_rows({m, kMaxCombinedTerms, kMaxCombinedTerms, work.coefficients.data(), work.sources.data(),
                        work.fields.data(), padded_m, padded_m, true, data.compliance.data(), stride});
  for (std::size_t p = 0; p < static_cast<std::size_t>(data.point_count); ++p) {
    const auto begin = static_cast<std::size_t>(data.point_first_row[p]),
               end = static_cast<std::size_t>(data.point_first_row[p + 1]);
    for (std::size_t r = begin; r < end; ++r)
      for (std::size_t s = begin; s <= r; ++s)
        data.compliance[r * stride + s] +=
            model.scene.point_compliance_m_per_n * data.rows[r].direction.dot(data.rows[s].direction);
  }
  kernels.mirror_lower(data.compliance.data(), m, stride);
}

/// The Gaussian decay of the tissue's compliance between two points.
double tissue_decay(const NeedleTissueModel& model, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double l = model.scene.compliance_correlation_length_m;
  return std::exp(-(a - b).squaredNorm() / (2.0 * l * l));
}

}  // namespace

SurfaceHit layer_hit(const NeedleTissueModel& model, const NeedleTissueData& data, int layer,
                     const Eigen::Vector3d& x_m, std::span<const double> displacements_m) noexcept {
  const TissueLayer& spec = model.scene.layers[static_cast<std::size_t>(layer)];
  if (spec.surface >= 0) {
    const SurfaceBvh& bvh = model.surface_bvhs[static_cast<std::size_t>(spec.surface)];
    return nearest_surface_point(bvh, data.surface_boxes.subspan(bvh.box_offset, 6 * bvh.nodes.size()),
                                 model.tissue_rest_m, displacements_m, x_m);
  }
  SurfaceHit hit;
  hit.normal = vec(spec.outward_normal);
  hit.distance_m = hit.normal.dot(
      x_m - tissue_point_position_m(data.layers[static_cast<std::size_t>(layer)].surface, displacements_m));
  hit.point_m = x_m - hit.distance_m * hit.normal;
  return hit;
}

NeedleFrameAt needle_frame_at(const NeedleModel& model, const NeedleData& data, double arclength_m) noexcept {
  NeedleFrameAt at;
  const double position = arclength_m / model.element_length_m;
  at.node = std::clamp(static_cast<int>(std::floor(position)), 0, model.element_count - 1);
  at.weight = std::clamp(position - at.node, 0.0, 1.0);
  const Eigen::Vector3d a = node_position_m(data.positions_m, at.node),
                        b = node_position_m(data.positions_m, at.node + 1);
  at.point_m = (1.0 - at.weight) * a + at.weight * b;
  at.tangent = (b - a).normalized();
  complete_frame(at.tangent, node_rotation(data.rotations_wxyz, at.node) * Eigen::Vector3d::UnitY(), at.normal1,
                 at.normal2);
  return at;
}

int cutting_layer(const NeedleTissueModel& model, const NeedleTissueData& data, const Eigen::Vector3d& tip_m,
                  std::span<const double> displacements_m) noexcept {
  for (int l = model.layer_count() - 1; l >= 0; --l)
    if (data.layers[static_cast<std::size_t>(l)].phase == LayerPhase::punctured &&
        layer_hit(model, data, l, tip_m, displacements_m).distance_m <= 0.0)
      return l;
  return -1;
}

Eigen::Vector3d bevel_force_n(const NeedleTissueModel& model, const NeedleTissueData& data) noexcept {
  if (model.bevel_tilt_rad == 0.0) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d side =
      node_rotation(data.needle.rotations_wxyz, model.needle.element_count) * Eigen::Vector3d::UnitY();
  return std::tan(model.bevel_tilt_rad) * data.slot_forces[static_cast<std::size_t>(model.tip_slot())] * side;
}

void build_rows(const NeedleTissueModel& model, NeedleTissueData& data,
                std::span<const double> displacements_m) noexcept {
  data.row_count = 0;
  const Eigen::Vector3d tip = needle_tip_m(data.needle);
  for (int l = 0; l < model.layer_count(); ++l) {
    LayerState& layer = data.layers[static_cast<std::size_t>(l)];
    if (layer.phase != LayerPhase::outside) {
      if (layer.phase == LayerPhase::touching) add_contact_rows(model, data, l, displacements_m);
      continue;
    }
    const SurfaceHit hit = layer_hit(model, data, l, tip, displacements_m);
    if (hit.distance_m < 0.0) {
      const Eigen::Vector3d& on_surface = hit.point_m;
      const bool through_hole =
          layer.holed &&
          (tissue_point_position_m(layer.hole, displacements_m) - on_surface).norm() <= model.scene.hole_radius_m;
      if (through_hole) {
        layer.phase = LayerPhase::punctured;
      } else {
        layer.phase = LayerPhase::touching;
        layer.contact = tissue_point_at(model, on_surface, displacements_m);
        layer.contact_normal = hit.normal;
      }
    }
    if (layer.phase == LayerPhase::touching) add_contact_rows(model, data, l, displacements_m);
  }
  const int cut = cutting_layer(model, data, tip, displacements_m);
  if (cut >= 0) add_tip_row(model, data, cut, displacements_m);
  for (int p = 0; p < model.scene.max_path_points; ++p)
    if (data.path[static_cast<std::size_t>(p)].active) add_path_rows(model, data, p, displacements_m);
}

void assemble_compliance(const NeedleTissueModel& model, NeedleTissueData& data) noexcept {
  const auto m = static_cast<std::size_t>(data.row_count), stride = padded(m);
  data.compliance_stride = stride;
  data.point_count = 0;
  if (m == 0) return;
  const int last_node = model.needle.element_count;
  int first_node = last_node;
  for (std::size_t r = 0; r < m; ++r) first_node = std::min(first_node, std::max(1, data.rows[r].node));
  update_needle_compliance(data.needle, first_node);
  // Constraint points (rows sharing a needle point and a tissue point).
  for (std::size_t r = 0; r < m; ++r) {
    const std::size_t first =
        data.point_count > 0
            ? static_cast<std::size_t>(data.point_first_row[static_cast<std::size_t>(data.point_count - 1)])
            : 0;
    if (r == 0 || r - first >= kMaxRowsPerPoint || !same_constraint_point(data.rows[first], data.rows[r]))
      data.point_first_row[static_cast<std::size_t>(data.point_count++)] = static_cast<std::int32_t>(r);
  }
  const auto points = static_cast<std::size_t>(data.point_count);
  data.point_first_row[points] = static_cast<std::int32_t>(m);
  const auto rows_of = [&](std::size_t p, std::size_t& begin, std::size_t& end) {
    begin = static_cast<std::size_t>(data.point_first_row[p]);
    end = static_cast<std::size_t>(data.point_first_row[p + 1]);
  };
  if (model.nodal_compliance()) {
    tissue_node_compliance(model, data);
    assemble_low_rank(model, data, first_node - 1);
    remove_applied_response(model, data);
    return;
  }
  for (std::size_t p = 0; p < points; ++p) {
    std::size_t p_begin = 0, p_end = 0;
    rows_of(p, p_begin, p_end);
    const ConstraintRow& at_p = data.rows[p_begin];
    for (std::size_t q = 0; q <= p; ++q) {
      std::size_t q_begin = 0, q_end = 0;
      rows_of(q, q_begin, q_end);
      const ConstraintRow& at_q = data.rows[q_begin];
      // The needle's compliance between the two interpolated points: sum_ab w_a w_b C_ab.
      Eigen::Matrix3d needle = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 2; ++i) {
        const int node_a = at_p.node + i;
        const double w_a = i == 0 ? 1.0 - at_p.weight : at_p.weight;
        if (node_a < 1 || w_a == 0.0) continue;
        for (int j = 0; j < 2; ++j) {
          const int node_b = at_q.node + j;
          const double w_b = j == 0 ? 1.0 - at_q.weight : at_q.weight;
          if (node_b < 1 || w_b == 0.0) continue;
          needle.noalias() += (w_a * w_b) * needle_compliance_block(data.needle, node_a, node_b);
        }
      }
      // The Gaussian kernel: the decay between the points times the tensor.
      const double decay = tissue_decay(model, at_p.tissue_point_m, at_q.tissue_point_m);
      const Eigen::Matrix3d& tissue = model.compliance_tensor_m_per_n;
      for (std::size_t r = p_begin; r < p_end; ++r) {
        ConstraintRow& row = data.rows[r];
        const Eigen::Vector3d needle_row = needle.transpose() * row.direction, tissue_row = tissue * row.direction;
        for (std::size_t s = q_begin; s < q_end && s <= r; ++s) {
          ConstraintRow& other = data.rows[s];
          const double tissue_entry = decay * other.direction.dot(tissue_row);
          data.compliance[r * stride + s] = data.compliance[s * stride + r] =
              needle_row.dot(other.direction) + tissue_entry;
          // The tissue displacements already hold its response to the applied forces.
          row.gap_free_m -= tissue_entry * data.applied_forces[static_cast<std::size_t>(other.slot)];
          if (s != r) other.gap_free_m -= tissue_entry * data.applied_forces[static_cast<std::size_t>(row.slot)];
        }
      }
    }
  }
}

Eigen::Vector3d compliant_displacement_m(const NeedleTissueModel& model, const NeedleTissueData& data,
                                         const Eigen::Vector3d& point_m, std::int32_t node) noexcept {
  const auto pending_n = [&](std::size_t r) {  // not yet carried by the tissue model
    return data.row_forces[r] - data.applied_forces[static_cast<std::size_t>(data.rows[r].slot)];
  };
  const int rank = model.compliance_rank;
  if (model.nodal_compliance()) {
    if (node < 0) return Eigen::Vector3d::Zero();
    Eigen::Vector3d u;
    if (rank > 0) {
      // u = -V_node sum_r V_r^T d_r pending_r, through the rank-sized sum.
      double sum[kMaxComplianceRank];
      factor_sum(model, data, pending_n, sum);
      const double* v = node_factors(model, node);
      u = -Eigen::Vector3d(dot(v, sum, rank), dot(v + rank, sum, rank), dot(v + 2 * rank, sum, rank));
    } else {
      u = -full_order_response(model, data, pending_n, node);
    }
    // What the tissue model misses yields under the whole forces: about the nodes near this
    // one, and locally at a constraint point's own tissue point.
    if (!model.missing_compliance.starts.empty()) {
      const auto whole_n = [&](std::size_t r) { return data.row_forces[r]; };
      for (std::size_t k = 0; k < static_cast<std::size_t>(data.distinct_tissue_node_count); ++k)
        if (const double* block = model.missing_compliance.find(node, data.distinct_tissue_nodes[k]))
          u -= Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(block) *
               force_on_distinct_node(data, k, whole_n);
    }
    for (int p = 0; p < data.point_count; ++p) {
      const auto begin = static_cast<std::size_t>(data.point_first_row[static_cast<std::size_t>(p)]);
      const auto end = static_cast<std::size_t>(data.point_first_row[static_cast<std::size_t>(p) + 1]);
      if (data.rows[begin].tissue_point_m != point_m) continue;
      for (std::size_t r = begin; r < end; ++r)
        u -= model.scene.point_compliance_m_per_n * data.row_forces[r] * data.rows[r].direction;
      break;
    }
    return u;
  }
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int p = 0; p < data.point_count; ++p) {
    const auto begin = static_cast<std::size_t>(data.point_first_row[static_cast<std::size_t>(p)]);
    const auto end = static_cast<std::size_t>(data.point_first_row[static_cast<std::size_t>(p) + 1]);
    Eigen::Vector3d force_n = Eigen::Vector3d::Zero();
    for (std::size_t r = begin; r < end; ++r) force_n += pending_n(r) * data.rows[r].direction;
    u -= tissue_decay(model, point_m, data.rows[begin].tissue_point_m) * (model.compliance_tensor_m_per_n * force_n);
  }
  return u;
}

}  // namespace nav::detail
