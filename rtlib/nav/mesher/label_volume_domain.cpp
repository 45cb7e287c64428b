#include "nav/mesher/label_volume_domain.hpp"

#include <algorithm>
#include <cmath>

#include "nav/mesher/distance_transform.hpp"

namespace nav {

LabelVolumeDomain::LabelVolumeDomain(const LabelVolume& volume)
    : spacing_m_(volume.spacing_m),
      min_spacing_m_(std::min({volume.spacing_m[0], volume.spacing_m[1], volume.spacing_m[2]})) {
  // The box of tissue voxels, widened by one background voxel on each side.
  std::array<std::int64_t, 3> lo{volume.size[0], volume.size[1], volume.size[2]};
  std::array<std::int64_t, 3> hi{-1, -1, -1};
  for (std::int64_t k = 0; k < volume.size[2]; ++k)
    for (std::int64_t j = 0; j < volume.size[1]; ++j)
      for (std::int64_t i = 0; i < volume.size[0]; ++i) {
        if (volume.at(i, j, k) == 0) continue;
        const std::int64_t index[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], index[a]);
          hi[a] = std::max(hi[a], index[a]);
        }
      }
  if (hi[0] < 0) lo = hi = {0, 0, 0};  // no tissue: a box of background samples only
  constexpr std::int64_t margin = 1;
  for (int a = 0; a < 3; ++a) {
    lo[a] -= margin;
    size_[a] = hi[a] - lo[a] + 1 + margin;
    origin_m_[a] = volume.origin_m[a] + static_cast<double>(lo[a]) * spacing_m_[a];
  }
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(size_[0] * size_[1] * size_[2]), 0);
  for (std::int64_t k = 0; k < size_[2]; ++k)
    for (std::int64_t j = 0; j < size_[1]; ++j)
      for (std::int64_t i = 0; i < size_[0]; ++i)
        inside[static_cast<std::size_t>(i + size_[0] * (j + size_[1] * k))] =
            volume.at(i + lo[0], j + lo[1], k + lo[2]) != 0;
  indicator_.assign(inside.begin(), inside.end());
  distance_m_ = signed_distance_map_m(inside, size_, spacing_m_);
}

Bounds3 LabelVolumeDomain::bounds() const {
  // The indicator exceeds 0.5 at most half a sample beyond the outermost kept samples.
  Bounds3 box;
  for (int a = 0; a < 3; ++a) {
    box.min_m[a] = origin_m_[a] - 0.5 * spacing_m_[a];
    box.max_m[a] = origin_m_[a] + (static_cast<double>(size_[a]) - 0.5) * spacing_m_[a];
  }
  return box;
}

double LabelVolumeDomain::interpolate(const std::vector<float>& samples, const Point3& point_m) const {
  // The kept box has at least three samples per axis (tissue plus a margin on each side).
  std::int64_t base[3];
  double fraction[3];
  for (int a = 0; a < 3; ++a) {
    const double u = std::clamp((point_m[a] - origin_m_[a]) / spacing_m_[a], 0.0, static_cast<double>(size_[a] - 1));
    base[a] = std::min(static_cast<std::int64_t>(u), size_[a] - 2);
    fraction[a] = u - static_cast<double>(base[a]);
  }
  double sum = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1;
    const int dj = (corner >> 1) & 1;
    const int dk = (corner >> 2) & 1;
    const double weight = (di ? fraction[0] : 1.0 - fraction[0]) * (dj ? fraction[1] : 1.0 - fraction[1]) *
                          (dk ? fraction[2] : 1.0 - fraction[2]);
    const std::int64_t index = base[0] + di + size_[0] * (base[1] + dj + size_[1] * (base[2] + dk));
    sum += weight * samples[static_cast<std::size_t>(index)];
  }
  return sum;
}

double LabelVolumeDomain::value(const Point3& point_m) const {
  // Outside the kept box the indicator is 0, as on the box's edge samples.
  return 0.5 - interpolate(indicator_, point_m);
}

Point3 LabelVolumeDomain::gradient(const Point3& point_m) const {
  // The distance map, continued beyond the kept box by the distance to the box.
  const Bounds3 box{origin_m_, origin_m_ + Point3{static_cast<double>(size_[0] - 1) * spacing_m_[0],
                                                  static_cast<double>(size_[1] - 1) * spacing_m_[1],
                                                  static_cast<double>(size_[2] - 1) * spacing_m_[2]}};
  return central_difference(point_m, gradient_step_m(), [&](const Point3& p) {
    Point3 clamped{};
    for (int a = 0; a < 3; ++a) clamped[a] = std::clamp(p[a], box.min_m[a], box.max_m[a]);
    return interpolate(distance_m_, clamped) + norm(p - clamped);
  });
}

}  // namespace nav
