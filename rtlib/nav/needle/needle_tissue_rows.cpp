#include "nav/needle/needle_tissue_rows.hpp"

#include <algorithm>
#include <cmath>

#include "nav/needle/needle_step.hpp"
#include "nav/needle/tissue_points.hpp"

namespace nav::detail {

namespace {

Eigen::Vector3d vec(const Point3& p) { return Eigen::Vector3d(p[0], p[1], p[2]); }

Eigen::Vector3d node_position(const NeedleData& data, int node) {
  return Eigen::Map<const Eigen::Vector3d>(data.positions_m.data() + 3 * static_cast<std::size_t>(node));
}

Eigen::Quaterniond node_rotation(const NeedleData& data, int node) {
  const double* q = data.rotations_wxyz.data() + 4 * static_cast<std::size_t>(node);
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

/// Two unit vectors completing `axis` to an orthonormal frame, the first taken from `hint`.
void complete_frame(const Eigen::Vector3d& axis, const Eigen::Vector3d& hint, Eigen::Vector3d& first, Eigen::Vector3d& second) {
  first = (hint - hint.dot(axis) * axis).normalized();
  second = axis.cross(first);
}

double signed_distance_m(const NeedleTissueModel& model, const NeedleTissueData& data, int layer, const Eigen::Vector3d& x,
                         std::span<const double> displacements_m) {
  const Eigen::Vector3d surface = tissue_point_position_m(data.layers[static_cast<std::size_t>(layer)].surface, displacements_m);
  return vec(model.scene.layers[static_cast<std::size_t>(layer)].outward_normal).dot(x - surface);
}

/// Appends one row and returns its index.
int add_row(NeedleTissueData& data, RowLaw law, int slot, int node, double weight, const Eigen::Vector3d& direction,
            const Eigen::Vector3d& needle_point_m, const Eigen::Vector3d& tissue_point_m, double cap, double mu) {
  ConstraintRow& row = data.rows[static_cast<std::size_t>(data.row_count)];
  row.law = law;
  row.slot = slot;
  row.node = node;
  row.weight = weight;
  row.direction = direction;
  row.tissue_point_m = tissue_point_m;
  row.gap_free_m = direction.dot(needle_point_m - tissue_point_m);
  row.cap = cap;
  row.friction_coefficient = mu;
  row.linked[0] = row.linked[1] = -1;
  data.row_forces[static_cast<std::size_t>(data.row_count)] = data.slot_forces[static_cast<std::size_t>(slot)];
  return data.row_count++;
}

void add_contact_rows(const NeedleTissueModel& model, NeedleTissueData& data, int layer, std::span<const double> displacements_m) {
  const TissueLayer& spec = model.scene.layers[static_cast<std::size_t>(layer)];
  const int tip_node = model.needle.element_count, slot = 3 * layer;
  const Eigen::Vector3d n = vec(spec.outward_normal), tip = needle_tip_m(data.needle);
  const Eigen::Vector3d contact = tissue_point_position_m(data.layers[static_cast<std::size_t>(layer)].contact, displacements_m);
  Eigen::Vector3d t1, t2;
  complete_frame(n, std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY(), t1, t2);
  const int normal = add_row(data, RowLaw::unilateral_capped, slot, tip_node, 0.0, n, tip, contact, spec.puncture_force_n, 0.0);
  const int first = add_row(data, RowLaw::coulomb_pair, slot + 1, tip_node, 0.0, t1, tip, contact, 0.0,
                            spec.surface_friction_coefficient);
  const int second = add_row(data, RowLaw::coulomb_second, slot + 2, tip_node, 0.0, t2, tip, contact, 0.0,
                             spec.surface_friction_coefficient);
  data.rows[static_cast<std::size_t>(first)].linked[0] = normal;
  data.rows[static_cast<std::size_t>(second)].linked[0] = normal;
}

void add_tip_row(const NeedleTissueModel& model, NeedleTissueData& data, int layer, std::span<const double> displacements_m) {
  const int tip_node = model.needle.element_count;
  const Eigen::Vector3d d = needle_tip_direction(data.needle), tip = needle_tip_m(data.needle);
  const Eigen::Vector3d front =
      tissue_point_position_m(data.layers[static_cast<std::size_t>(layer)].cut_front, displacements_m);
  add_row(data, RowLaw::unilateral_capped, model.tip_slot(), tip_node, 0.0, -d, tip, front,
          model.scene.layers[static_cast<std::size_t>(layer)].cutting_force_n, 0.0);
}

void add_path_rows(const NeedleTissueModel& model, NeedleTissueData& data, int point, std::span<const double> displacements_m) {
  const PathPoint& path = data.path[static_cast<std::size_t>(point)];
  const NeedleFrameAt at = needle_frame_at(model.needle, data.needle, path.arclength_m);
  const Eigen::Vector3d tissue = tissue_point_position_m(path.tissue, displacements_m);
  const int slot = model.path_slot(point);
  const TissueLayer& layer = model.scene.layers[static_cast<std::size_t>(path.layer)];
  const int first = add_row(data, RowLaw::bilateral, slot, at.node, at.weight, at.normal1, at.point_m, tissue, 0.0, 0.0);
  const int second = add_row(data, RowLaw::bilateral, slot + 1, at.node, at.weight, at.normal2, at.point_m, tissue, 0.0, 0.0);
  const int axial = add_row(data, RowLaw::friction_axial, slot + 2, at.node, at.weight, at.tangent, at.point_m, tissue,
                            layer.friction_per_length_n_m * model.scene.path_spacing_m, model.scene.shaft_friction_coefficient);
  data.rows[static_cast<std::size_t>(axial)].linked[0] = first;
  data.rows[static_cast<std::size_t>(axial)].linked[1] = second;
}

/// n_r^T (sum of the needle's compliance blocks between the rows' interpolation nodes) n_s.
double needle_coupling(const NeedleData& needle, const ConstraintRow& r, const ConstraintRow& s) {
  double sum = 0.0;
  for (int a = 0; a < 2; ++a) {
    const int node_a = r.node + a;
    const double wa = a == 0 ? 1.0 - r.weight : r.weight;
    if (node_a < 1 || wa == 0.0) continue;
    for (int b = 0; b < 2; ++b) {
      const int node_b = s.node + b;
      const double wb = b == 0 ? 1.0 - s.weight : s.weight;
      if (node_b < 1 || wb == 0.0) continue;
      const Eigen::Map<const Eigen::Matrix3d> c(needle_compliance_block(needle, node_a, node_b));
      sum += wa * wb * r.direction.dot(c * s.direction);
    }
  }
  return sum;
}

double tissue_kernel(const NeedleTissueModel& model, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double l = model.scene.compliance_correlation_length_m;
  return model.scene.point_compliance_m_per_n * std::exp(-(a - b).squaredNorm() / (2.0 * l * l));
}

}  // namespace

NeedleFrameAt needle_frame_at(const NeedleModel& model, const NeedleData& data, double arclength_m) noexcept {
  NeedleFrameAt at;
  const double position = arclength_m / model.element_length_m;
  at.node = std::clamp(static_cast<int>(std::floor(position)), 0, model.element_count - 1);
  at.weight = std::clamp(position - at.node, 0.0, 1.0);
  const Eigen::Vector3d a = node_position(data, at.node), b = node_position(data, at.node + 1);
  at.point_m = (1.0 - at.weight) * a + at.weight * b;
  at.tangent = (b - a).normalized();
  complete_frame(at.tangent, node_rotation(data, at.node) * Eigen::Vector3d::UnitY(), at.normal1, at.normal2);
  return at;
}

int cutting_layer(const NeedleTissueModel& model, const NeedleTissueData& data, const Eigen::Vector3d& tip_m,
                  std::span<const double> displacements_m) noexcept {
  for (int l = model.layer_count() - 1; l >= 0; --l)
    if (data.layers[static_cast<std::size_t>(l)].phase == LayerPhase::punctured &&
        signed_distance_m(model, data, l, tip_m, displacements_m) <= 0.0)
      return l;
  return -1;
}

Eigen::Vector3d bevel_force_n(const NeedleTissueModel& model, const NeedleTissueData& data) noexcept {
  if (model.bevel_tilt_rad == 0.0) return Eigen::Vector3d::Zero();
  const double* q = data.needle.rotations_wxyz.data() + 4 * static_cast<std::size_t>(model.needle.element_count);
  const Eigen::Vector3d side = Eigen::Quaterniond(q[0], q[1], q[2], q[3]) * Eigen::Vector3d::UnitY();
  return std::tan(model.bevel_tilt_rad) * data.slot_forces[static_cast<std::size_t>(model.tip_slot())] * side;
}

void build_rows(const NeedleTissueModel& model, NeedleTissueData& data, std::span<const double> displacements_m) noexcept {
  data.row_count = 0;
  const Eigen::Vector3d tip = needle_tip_m(data.needle);
  for (int l = 0; l < model.layer_count(); ++l) {
    LayerState& layer = data.layers[static_cast<std::size_t>(l)];
    const double distance_m = signed_distance_m(model, data, l, tip, displacements_m);
    if (layer.phase == LayerPhase::outside && distance_m < 0.0) {
      const Eigen::Vector3d on_surface = tip - distance_m * vec(model.scene.layers[static_cast<std::size_t>(l)].outward_normal);
      const bool through_hole =
          layer.holed && (tissue_point_position_m(layer.hole, displacements_m) - on_surface).norm() <= model.scene.hole_radius_m;
      if (through_hole) {
        layer.phase = LayerPhase::punctured;
      } else {
        layer.phase = LayerPhase::touching;
        layer.contact = tissue_point_at(model, on_surface, displacements_m);
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
  const auto m = static_cast<std::size_t>(data.row_count);
  if (m == 0) return;
  int first_node = model.needle.element_count;
  for (std::size_t r = 0; r < m; ++r) first_node = std::min(first_node, std::max(1, data.rows[r].node));
  update_needle_compliance(data.needle, first_node);
  for (std::size_t r = 0; r < m; ++r) {
    ConstraintRow& row = data.rows[r];
    for (std::size_t s = 0; s <= r; ++s) {
      const ConstraintRow& other = data.rows[s];
      const double tissue = tissue_kernel(model, row.tissue_point_m, other.tissue_point_m) * row.direction.dot(other.direction);
      const double w = needle_coupling(data.needle, row, other) + tissue;
      data.compliance[r * m + s] = data.compliance[s * m + r] = w;
      row.gap_free_m += tissue * data.applied_forces[static_cast<std::size_t>(other.slot)];
      if (s != r) data.rows[s].gap_free_m += tissue * data.applied_forces[static_cast<std::size_t>(row.slot)];
    }
  }
}

Eigen::Vector3d compliant_displacement_m(const NeedleTissueModel& model, const NeedleTissueData& data,
                                         const Eigen::Vector3d& point_m) noexcept {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int r = 0; r < data.row_count; ++r) {
    const ConstraintRow& row = data.rows[static_cast<std::size_t>(r)];
    const double pending = data.row_forces[static_cast<std::size_t>(r)] - data.applied_forces[static_cast<std::size_t>(row.slot)];
    u -= tissue_kernel(model, point_m, row.tissue_point_m) * pending * row.direction;
  }
  return u;
}

}  // namespace nav::detail
