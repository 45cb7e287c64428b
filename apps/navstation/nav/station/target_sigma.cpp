#include "nav/station/target_sigma.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace nav::station {

double sigma_radius_m(const dds::Covariance3& covariance_m2) {
  const Eigen::Matrix3d covariance = Eigen::Map<const Eigen::Matrix3d>(covariance_m2.data());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(0.5 * (covariance + covariance.transpose()), Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
}

}  // namespace nav::station
