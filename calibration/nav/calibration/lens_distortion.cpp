#include "nav/calibration/lens_distortion.hpp"

namespace nav::calibration {
namespace {

/// The radial factor and the tangential offset of the lens at the normalised point `p`.
struct DistortionTerms {
  double radial = 1.0;
  Eigen::Vector2d tangential = Eigen::Vector2d::Zero();
};

DistortionTerms terms(const LensDistortion& lens, const Eigen::Vector2d& p) noexcept {
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  return {1.0 + r2 * (lens.k1 + r2 * (lens.k2 + r2 * lens.k3)),
          {2.0 * lens.p1 * x * y + lens.p2 * (r2 + 2.0 * x * x), lens.p1 * (r2 + 2.0 * y * y) + 2.0 * lens.p2 * x * y}};
}

}  // namespace

Eigen::Vector2d distort(const LensDistortion& lens, const Eigen::Vector2d& ideal) noexcept {
  const DistortionTerms t = terms(lens, ideal);
  return ideal * t.radial + t.tangential;
}

Eigen::Vector2d undistort(const LensDistortion& lens, const Eigen::Vector2d& distorted) noexcept {
  constexpr int kIterations = 30;
  Eigen::Vector2d ideal = distorted;
  for (int i = 0; i < kIterations; ++i) {
    const DistortionTerms t = terms(lens, ideal);
    ideal = (distorted - t.tangential) / t.radial;
  }
  return ideal;
}

}  // namespace nav::calibration
