#pragma once
// The tissue of a label volume as a meshing domain.
#include <array>
#include <cstdint>
#include <vector>

#include "nav/mesher/label_volume.hpp"
#include "nav/mesher/level_set_domain.hpp"

namespace nav {

/// The region where the trilinear interpolation of the tissue indicator (1 at the centre of a
/// voxel with a non-zero label, 0 elsewhere and outside the grid) exceeds 0.5; the field is
/// 0.5 minus that interpolation. Projection goes to the 0.5 level by bisection along the
/// gradient of the voxels' signed distance map, which, unlike the indicator, is not flat away
/// from the boundary.
class LabelVolumeDomain final : public LevelSetDomain {
 public:
  /// Keeps the indicator and distance map of `volume` over the box of its tissue voxels
  /// (plus a margin of background).
  explicit LabelVolumeDomain(const LabelVolume& volume);

  Bounds3 bounds() const override;
  double value(const Point3& point_m) const override;
  Point3 gradient(const Point3& point_m) const override;

 protected:
  double gradient_step_m() const override { return 0.5 * min_spacing_m_; }
  double march_step_m() const override { return 0.25 * min_spacing_m_; }

 private:
  /// Trilinear interpolation of per-sample values, the samples clamped to the kept box.
  double interpolate(const std::vector<float>& samples, const Point3& point_m) const;

  std::array<std::int64_t, 3> size_{};  ///< samples of the kept box per axis
  Point3 spacing_m_{};
  Point3 origin_m_{};  ///< centre of sample (0, 0, 0)
  std::vector<float> indicator_;
  std::vector<float> distance_m_;  ///< signed distance map, negative inside
  double min_spacing_m_;
};

}  // namespace nav
