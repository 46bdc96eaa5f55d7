// The fuser's output: a bounded, time-indexed buffer of lidar states at the
// IMU rate, and the two queries the 10 Hz pipeline makes per point
// (docs/method.md §1–3):
//  - the lidar pose at any time, for de-skewing: linear in position, slerp in
//    rotation between the two samples around t (paper §III-B);
//  - the skew perturbations δ_k = ∫σ_v(|v_k|)dt and θ_k = ∫σ_ω(|ω_k|)dt from
//    the scan start to the point's time, for VTW/GVTW.
//
// δ/θ cost O(1) per point: every sample stores the running integral of its σ's
// (prefix sums), so ∫_{t_a}^{t_b} = C(t_b) − C(t_a), with C inside a segment
// = the prefix at its start + the partial trapezoid. The integrand is the σ
// evaluated at the samples and linear in between (the same piecewise-linear
// convention as the pose). Both σ pairs (de-skewed and raw) are kept, so the
// pipeline can switch de-skewing without the fuser knowing.
//
// Frame of δ, θ: the LIDAR frame. The perturbations are applied to points
// expressed in the lidar frame (rot(p, ±θ) ± δ), and the paper's σ models were
// fitted per sensor axis (speeds along/about the axes of the moving sensor on
// the rail and turntable), so the speeds fed to them are v_L = R_LW v_W and
// ω_L. Each axis' σ is a magnitude, not a vector, so it is integrated as such
// in the instantaneous lidar axes (rotating magnitudes between frames would
// have no meaning); this is also what the authors' implementation does.
//
// Ends (documented choice): queries before the first or after the last sample
// extrapolate with that end sample's velocity and body rate (constant twist),
// and the σ integrands are held constant there. Callers that need real data can
// check t_begin_s()/t_end_s().
//
// Memory: a fixed-capacity ring; pushing into a full buffer drops the oldest
// sample. No allocation after construction, and copy-assigning into a
// Trajectory of equal capacity does not allocate either (std::vector reuses
// its storage), which is how a reader thread can take a snapshot.
#pragma once

#include <array>
#include <cstddef>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/ring_buffer.hpp"
#include "core/speed_uncertainty.hpp"

namespace tumble {

struct TrajectorySample {
  double t_s = 0.0;
  Eigen::Quaterniond q_wl = Eigen::Quaterniond::Identity();  // lidar attitude
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();             // lidar origin in W
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();             // velocity of the lidar origin, in W
  Eigen::Vector3d omega_l = Eigen::Vector3d::Zero();         // angular velocity, lidar frame (rad/s)
  // The variance of v_w per W axis as the fuser had it at this sample ((m/s)²;
  // zero where nothing estimated it, as in a prediction).
  Eigen::Vector3d velocity_var_w_m2_s2 = Eigen::Vector3d::Zero();
  // Clipping that touches lidar axis k (union of the two below).
  std::array<bool, 3> saturated{};
  // A clipped gyro axis couples into lidar axis k: ω_k is not known.
  std::array<bool, 3> gyro_saturated{};
  // An accelerometer clip since the last lidar velocity correction couples into
  // lidar axis k: the integrated speed along it is not known.
  std::array<bool, 3> accel_saturated{};
};

// δ (m) and θ (rad) per lidar axis.
struct SkewPerturbation {
  Eigen::Vector3d delta_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d theta_rad = Eigen::Vector3d::Zero();
};

class Trajectory {
 public:
  Trajectory(std::size_t capacity, const SpeedUncertaintyParams& params);

  // Appends a sample; times must strictly increase (std::invalid_argument
  // otherwise, naming both times).
  void push_back(const TrajectorySample& sample);
  // Drops every sample later than t_s (the fuser rewrites its tail after a
  // lidar correction).
  void truncate_after(double t_s);
  void clear();

  std::size_t size() const { return ring_.size(); }
  bool empty() const { return ring_.empty(); }
  std::size_t capacity() const { return ring_.capacity(); }
  // 0 = oldest.
  const TrajectorySample& operator[](std::size_t i) const { return ring_[i].sample; }
  const TrajectorySample& front() const { return ring_.front().sample; }
  const TrajectorySample& back() const { return ring_.back().sample; }
  double t_begin_s() const { return front().t_s; }
  double t_end_s() const { return back().t_s; }
  const SpeedUncertaintyParams& speed_uncertainty() const { return params_; }

  // T_WL(t). Throws std::logic_error when empty (as do all queries).
  Eigen::Isometry3d pose_at(double t_s) const;
  // v_W(t), linear between samples (the end sample's beyond either end).
  Eigen::Vector3d velocity_at(double t_s) const;
  // The velocity variance of the newest sample at or before t (the first's before it).
  Eigen::Vector3d velocity_variance_at(double t_s) const;
  // T_WL(t_from)⁻¹ · T_WL(t_to): the motion between two times, which is all
  // de-skewing and the registration's initial guess need.
  Eigen::Isometry3d relative_pose(double t_from_s, double t_to_s) const;
  // ∫_{t_from}^{t_to} of the per-axis σ's; `deskewed` selects the σ pair.
  SkewPerturbation skew_integral(double t_from_s, double t_to_s, bool deskewed) const;

  // As above, with a segment hint: pass the same variable for successive
  // queries at (nearly) increasing times and each lookup is O(1). Any value is
  // safe; a stale hint only costs a binary search.
  Eigen::Isometry3d pose_at(double t_s, std::size_t& hint) const;
  SkewPerturbation cumulative_skew(double t_s, bool deskewed, std::size_t& hint) const;

 private:
  struct SpeedSigmas {
    Eigen::Vector3d linear_m_s = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_rad_s = Eigen::Vector3d::Zero();
  };
  struct Entry {
    TrajectorySample sample;
    std::array<SpeedSigmas, 2> sigma;             // [raw, de-skewed] at this sample
    std::array<SkewPerturbation, 2> cumulative;   // running ∫σ up to this sample
  };

  // Index i of the segment [i, i+1] holding t, clamped to the buffer (size ≥ 2).
  std::size_t locate(double t_s, std::size_t& hint) const;

  friend class RelativePoseInterpolator;

  RingBuffer<Entry> ring_;
  SpeedUncertaintyParams params_;
};

// T_WL(t_ref)⁻¹ T_WL(t) for points of one scan, in (nearly) time order: the
// de-skew transform of a point fired at t into the lidar frame at t_ref.
//
// Per point (de-skewing runs it on every return): the segment around t is
// prepared once in the reference frame (slerp is linear in the quaternions'
// coefficients, so T_ref⁻¹ distributes over it), leaving two sines of small
// angles (a short series, exact to rounding) and a quaternion rotation.
class RelativePoseInterpolator {
 public:
  RelativePoseInterpolator(const Trajectory& trajectory, double t_ref_s);
  Eigen::Isometry3d to_reference(double t_s);
  // to_reference(t_s) * p, without forming the pose.
  Eigen::Vector3d point_to_reference(double t_s, const Eigen::Vector3d& p);

 private:
  // The segment [i, i+1] in the reference frame; false outside the samples.
  bool prepare(double t_s);

  const Trajectory& trajectory_;
  Eigen::Isometry3d reference_inverse_;
  std::size_t hint_ = 0;
  std::size_t segment_ = static_cast<std::size_t>(-1);
  double t_a_s_ = 0, t_b_s_ = 0, inv_dt_ = 0;
  double theta_ = 0, inv_sin_theta_ = 0;  // slerp angle; theta_ = 0: linear weights
  Eigen::Vector4d qa_ = Eigen::Vector4d::Zero(), qb_ = Eigen::Vector4d::Zero();  // q_ref⁻¹ q_a, ±q_ref⁻¹ q_b (x y z w)
  Eigen::Vector3d pa_ = Eigen::Vector3d::Zero(), dp_ = Eigen::Vector3d::Zero();  // R_refᵀ(p_a − p_ref), R_refᵀ(p_b − p_a)
};

// δ, θ from a scan start to the points' times, O(1) per point in time order.
class SkewIntegrator {
 public:
  SkewIntegrator(const Trajectory& trajectory, double t_start_s, bool deskewed);
  SkewPerturbation until(double t_s);

 private:
  const Trajectory& trajectory_;
  bool deskewed_;
  SkewPerturbation start_;
  std::size_t hint_ = 0;
};

}  // namespace tumble
