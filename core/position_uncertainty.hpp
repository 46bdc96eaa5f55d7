// How well the registered position is known from one scan to the next
// (ours): a Kalman filter on the position error alone. The IMU's prediction
// of the next scan's pose is good to about a centimetre per scan interval;
// where a scan pins its pose only weakly (a lane, a sparse yard) ICP's step
// along the weak direction follows the normals' noise and is worse than the
// prediction (docs/decisions/prediction-prior.md). So the prediction enters
// ICP as a prior (Icp::align), and the published position covariance is the
// fusion of the prediction's and the scan's: small where either pins the
// pose, growing by the prediction's each scan that pins a direction no
// better than it.
// The prediction is no better than the fuser's velocity: its variance over
// the time since the last update adds to the prediction's, so after an IMU
// gap or a jump, when the velocity is a guess, the prior lets go and the
// scans measure it again instead of confirming it.
//
// The prior weighs against the ICP's own s²·H⁻¹ scaled by κ², while the
// fusion takes the published covariance (the normals' noise discounted, the
// floor, the widenings): the ICP sees the information it solves with, the
// published figure what the calibration says it is worth.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "core/icp.hpp"

namespace tumble {

struct PositionUncertaintyParams {
  // σ per W axis of the predicted position over one scan interval (0: no
  // prior, the paper's ICP; tumbled's default is 0.02).
  double prediction_sigma_m = 0.0;
  // The interval σ is for; a longer one (scans lost or skipped, a short lidar
  // gap) grows it in proportion: a velocity error carries on.
  double scan_interval_s = 0.1;
  // A registered position this many σ of the prediction away from it (the
  // Mahalanobis distance of the correction against the predicted and the
  // scan's position covariances) is a jump: either the prediction or the
  // scan is wrong, so it is not published as good and its velocity is not
  // measured (ImuFuser, header 8). 0: no test (the paper's ICP).
  double jump_sigmas = 0.0;
};

// Throws std::invalid_argument naming the parameter out of range.
void check_position_uncertainty_params(const PositionUncertaintyParams& params);

class PositionUncertainty {
 public:
  explicit PositionUncertainty(const PositionUncertaintyParams& params);

  bool enabled() const { return params_.prediction_sigma_m > 0; }
  // The time of the last update (-inf before any): what the prediction of
  // the next scan spans from.
  double updated_at_s() const { return updated_at_s_; }
  // The covariance of the predicted position at t_s (W axes, m²): the last
  // update's plus the prediction's error since.
  // `velocity_var_w_m2_s2`: the fuser's velocity variance per W axis.
  Eigen::Matrix3d predicted(double t_s, const Eigen::Vector3d& velocity_var_w_m2_s2 = Eigen::Vector3d::Zero()) const;
  // The same as an information matrix for Icp::align, in the units of the
  // ICP's own covariance: `covariance_scale` is the calibration κ of that
  // covariance (registration_confidence.hpp). Zero when disabled.
  Eigen::Matrix3d prior_information(double t_s, double covariance_scale,
                                    const Eigen::Vector3d& velocity_var_w_m2_s2 = Eigen::Vector3d::Zero()) const;
  // Whether a registered position `correction_w_m` from the prediction is a
  // jump (PositionUncertaintyParams::jump_sigmas) against the prediction's
  // and the scan's published position covariances. Never when disabled.
  // Without the velocity's variance: however uncertain the velocity, a
  // velocity measured across a jump is wrong, since either the pose before
  // it or the one after it is (after an IMU gap, a correct scan 50 cm from
  // a wrong prediction made the next velocity 5 m/s off).
  bool jumped(double t_s, const Eigen::Vector3d& correction_w_m, const Eigen::Matrix3d& scan_position_covariance) const;

  // A scan at t_s registered with the prior: fuses the predicted position
  // with the scan's published covariance (6×6, translation first) and
  // returns the fused one, whose position block is kept for the next scan.
  // A scan covariance that is not finite: as predict_only(), returned as is.
  Matrix6d fuse(double t_s, const Matrix6d& scan_covariance,
                const Eigen::Vector3d& velocity_var_w_m2_s2 = Eigen::Vector3d::Zero());
  // A scan registered without the prior: its position covariance as it is
  // (not finite: as predict_only()).
  void replace_with_scan(double t_s, const Matrix6d& scan_covariance,
                         const Eigen::Vector3d& velocity_var_w_m2_s2 = Eigen::Vector3d::Zero());
  // A scan not registered: the prediction carried the pose.
  void predict_only(double t_s, const Eigen::Vector3d& velocity_var_w_m2_s2 = Eigen::Vector3d::Zero());
  // A new local map: its first pose defines it.
  void reset(double t_s);

 private:
  PositionUncertaintyParams params_;
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Zero();
  double updated_at_s_ = -std::numeric_limits<double>::infinity();
};

}  // namespace tumble
