#pragma once
// What the embedding example's simulated devices see: the patient's true motion over time
// (breathing, the diaphragm, the tumour by the full-order model, a needle inserted toward the
// tumour) and the noisy, delayed samples a tracker and an ultrasound tumour detector make of
// it. In real station software these come from its own drivers; here they are functions of
// the run time (seconds since the loop started) and seeded noise.
#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "nav/fusion/rigid_pose.hpp"
#include "station_liver_loop.hpp"

namespace embedding {

/// The patient's true motion. The respiratory marker on the skin rises along the tracker's z;
/// the diaphragm inside moves further than the marker and later (the marker is only a
/// surrogate: the ultrasound has to make up the difference).
struct PatientMotion {
  double marker_rest_z_m = 0.10;  ///< respiratory marker height at mid-breath
  double marker_amplitude_m = 0.005;
  double period_s = 3.0;
  double diaphragm_gain = 1.3;  ///< diaphragm lift per marker rise
  double diaphragm_lag_s = 0.2;
  Eigen::Vector3d needle_entry_m;                    ///< where the tip starts (model frame)
  Eigen::Vector3d needle_direction{0.0, -1.0, 0.0};  ///< unit, toward the tumour
  double needle_speed_m_s = 0.004;
  double needle_length_m = 0.15;

  double marker_rise_m(double t_s) const {
    return marker_amplitude_m * std::sin(2.0 * std::numbers::pi * t_s / period_s);
  }
  double diaphragm_lift_m(double t_s) const { return diaphragm_gain * marker_rise_m(t_s - diaphragm_lag_s); }
  Eigen::Vector3d needle_tip_m(double t_s) const { return needle_entry_m + needle_speed_m_s * t_s * needle_direction; }
  /// The needle marker: its -z axis along the needle, the tip needle_length_m from it.
  nav::RigidPose needle_marker(double t_s) const {
    nav::RigidPose pose;
    pose.rotation = Eigen::Quaterniond::FromTwoVectors(-Eigen::Vector3d::UnitZ(), needle_direction);
    pose.position_m = needle_tip_m(t_s) - needle_length_m * needle_direction;
    return pose;
  }
};

/// Seeded measurement noise of the simulated devices.
class DeviceNoise {
 public:
  explicit DeviceNoise(std::uint64_t seed, double std_m) : rng_(seed), normal_(0.0, std_m) {}
  Eigen::Vector3d operator()() { return {normal_(rng_), normal_(rng_), normal_(rng_)}; }

 private:
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_;
};

}  // namespace embedding
