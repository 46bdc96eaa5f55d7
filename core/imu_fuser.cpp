// See imu_fuser.hpp for the method and the choices.
#include "core/imu_fuser.hpp"

#include <cmath>
#include <stdexcept>

#include "core/rotation.hpp"

namespace tumble {

namespace {

// A direction cosine above this couples one axis into another (clip flags).
constexpr double kAxisCoupling = 0.1;
// The velocity variance published while it is unknown (waiting for rest): 10 m/s, 1 σ.
constexpr double kUnknownVelocityVariance_m2_s2 = 100.0;

bool any(const std::array<bool, 3>& flags) { return flags[0] || flags[1] || flags[2]; }

// R_WL levelled with gravity and keeping the lidar's heading: W's z is "up"
// (up_l, in lidar coordinates), W's x is the lidar's x projected on the
// horizontal plane (its y when x points straight up or down).
Eigen::Quaterniond levelled_lidar_attitude(const Eigen::Vector3d& up_l) {
  const Eigen::Vector3d z = up_l.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitY() - z.y() * z;
  x.normalize();
  Eigen::Matrix3d r_lw;  // columns: W's axes in lidar coordinates
  r_lw.col(0) = x;
  r_lw.col(1) = z.cross(x);
  r_lw.col(2) = z;
  return Eigen::Quaterniond(r_lw.transpose());
}

}  // namespace

ImuFuser::ImuFuser(const ImuFuserParams& params)
    : params_(params),
      q_li_(Eigen::Quaterniond(params.T_li.rotation()).normalized()),
      p_il_(-(q_li_.conjugate() * params.T_li.translation())),
      process_noise_psd_(params.accel_noise_density_m_s2_sqrt_hz * params.accel_noise_density_m_s2_sqrt_hz +
                         params.accel_unmodelled_m_s2 * params.accel_unmodelled_m_s2 * 1.0 /* s */),
      madgwick_(params.madgwick, Eigen::Quaterniond::Identity(), kStandardGravity_m_s2),
      history_(params.history_capacity),
      trajectory_(params.trajectory_capacity, params.speed_uncertainty) {
  if (params.history_capacity < 2) throw std::invalid_argument("ImuFuser: history_capacity must be at least 2");
  if (!(params.static_duration_s >= 0.0)) throw std::invalid_argument("ImuFuser: static_duration_s must be >= 0");
  if (!(params.rest_duration_s >= 0.0)) throw std::invalid_argument("ImuFuser: rest_duration_s must be >= 0");
}

Eigen::Vector3d ImuFuser::velocity_variance() const {
  return history_.empty() ? Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity())
                          : history_.back().state.variance;
}

Eigen::Vector3d ImuFuser::gravity_free_accel(const Eigen::Quaterniond& q_wi, const Eigen::Vector3d& accel_i) const {
  return q_wi * accel_i - Eigen::Vector3d(0.0, 0.0, gravity_m_s2_);
}

void ImuFuser::integrate(KinematicState& state, const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                         double dt_s) const {
  const Eigen::Vector3d v1 = state.v_w + 0.5 * dt_s * (a0 + a1);
  const Eigen::Vector3d mean_velocity = 0.5 * (state.v_w + v1);
  state.p_w += dt_s * mean_velocity;
  state.v_integral += dt_s * mean_velocity;
  state.v_w = v1;
  state.variance.array() += process_noise_psd_ * dt_s;
}

Eigen::Vector3d ImuFuser::unclipped_gyro(const Eigen::Vector3d& gyro_clipped_i,
                                         const std::array<bool, 3>& clipped) const {
  Eigen::Vector3d gyro = gyro_clipped_i;
  if (!lidar_rate_i_rad_s_) return gyro;
  for (int j = 0; j < 3; ++j) {
    const double lidar = (*lidar_rate_i_rad_s_)[j];
    if (clipped[static_cast<std::size_t>(j)] && lidar * gyro[j] > 0.0 && std::abs(lidar) > std::abs(gyro[j]))
      gyro[j] = lidar;
  }
  return gyro;
}

ImuFuser::HistoryEntry ImuFuser::measured_entry(const ImuSample& sample) const {
  HistoryEntry entry;
  entry.t_s = sample.t_s;
  entry.accel_i = sample.accel_m_s2;
  entry.gyro_clipped_i = sample.gyro_rad_s - gyro_bias_;
  entry.accel_clipped = sample.accel_saturated;
  entry.gyro_clipped = sample.gyro_saturated;
  entry.gyro_i = any(entry.gyro_clipped) ? unclipped_gyro(entry.gyro_clipped_i, entry.gyro_clipped)
                                         : entry.gyro_clipped_i;
  return entry;
}

void ImuFuser::add_clip_noise(KinematicState& state, const HistoryEntry& entry, double dt_s) const {
  if (!any(entry.accel_clipped)) return;
  const Eigen::Matrix3d r_wi = entry.q_wi.toRotationMatrix();
  const double sigma = params_.saturated_accel_sigma_m_s2 * dt_s;
  for (int j = 0; j < 3; ++j) {
    if (!entry.accel_clipped[static_cast<std::size_t>(j)]) continue;
    const Eigen::Vector3d direction = r_wi.col(j);  // the clipped axis, in W
    state.variance += sigma * sigma * direction.cwiseAbs2();
    for (int i = 0; i < 3; ++i) {
      if (std::abs(direction[i]) > kAxisCoupling) state.speed_unknown[static_cast<std::size_t>(i)] = true;
    }
  }
}

void ImuFuser::add_imu(const ImuSample& sample) {
  if (initialized_) {
    if (!(sample.t_s > history_.back().t_s)) {
      ++stats_.samples_out_of_order;
      return;
    }
  } else {
    if (!(sample.t_s > last_input_t_s_)) {
      ++stats_.samples_out_of_order;
      return;
    }
    last_input_t_s_ = sample.t_s;
    accumulate_static(sample);
    return;
  }

  const HistoryEntry& previous = history_.back();
  if (awaiting_rest_) {
    add_imu_awaiting_rest(sample, previous);
    return;
  }
  const double dt = sample.t_s - previous.t_s;
  if (dt > params_.max_imu_gap_s) {
    ++stats_.imu_gaps;
    if (anchor_ && (previous_anchor_ || previous_registration_)) {
      reanchor(sample);
      return;
    }
  }

  HistoryEntry entry = measured_entry(sample);
  if (entry.gyro_i != entry.gyro_clipped_i) ++stats_.gyro_samples_from_lidar;

  if (params_.attitude_from_device && sample.has_orientation) {
    if (!device_alignment_) device_alignment_ = madgwick_.orientation() * sample.orientation.conjugate();
    madgwick_.set_orientation(*device_alignment_ * sample.orientation);
  } else if (!step_attitude(madgwick_, entry, dt)) {
    ++stats_.accel_gated;
  }
  entry.q_wi = madgwick_.orientation();
  entry.accel_w = gravity_free_accel(entry.q_wi, entry.accel_i);
  entry.state = previous.state;
  integrate(entry.state, previous.accel_w, entry.accel_w, dt);
  add_clip_noise(entry.state, entry, dt);

  if (!velocity_confirmed_ && completes_still_window(sample, params_.rest_duration_s)) {
    rests_to_check_.push_back(sample.t_s);
    restart_still_window();
  }
  history_.push_back(entry);
  trajectory_.push_back(to_trajectory_sample(entry));
  ++stats_.samples;
  if (any(entry.gyro_clipped)) ++stats_.gyro_saturated_samples;
  if (any(entry.accel_clipped)) ++stats_.accel_saturated_samples;
}

void ImuFuser::reanchor(const ImuSample& sample) {
  const RegisteredPose& a = *anchor_;
  const RegisteredPose& b = previous_anchor_ ? *previous_anchor_ : *previous_registration_;
  const double dt_ab = std::max(a.t_s - b.t_s, 1e-3);
  const Eigen::Vector3d v_wi = (a.p_wi - b.p_wi) / dt_ab;
  const Eigen::AngleAxisd turn((b.q_wi.conjugate() * a.q_wi).normalized());
  const Eigen::Vector3d rate_i = turn.angle() * turn.axis() / dt_ab;
  const double h = sample.t_s - a.t_s;
  const Eigen::Vector3d rotation_i = rate_i * h;
  const Eigen::Quaterniond step =
      rotation_i.norm() > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(rotation_i.norm(), rotation_i.normalized()))
                            : Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond q_wi = (a.q_wi * step).normalized();
  madgwick_.set_orientation(q_wi);
  if (device_alignment_ && sample.has_orientation) device_alignment_ = q_wi * sample.orientation.conjugate();

  HistoryEntry entry = measured_entry(sample);
  entry.q_wi = q_wi;
  entry.accel_w = gravity_free_accel(q_wi, entry.accel_i);
  entry.state.v_w = v_wi;
  entry.state.p_w = a.p_wi + v_wi * h;
  const double bridged_var = params_.bridged_velocity_sigma_m_s * params_.bridged_velocity_sigma_m_s;
  entry.state.variance.setConstant(
      std::max((a.sigma_m * a.sigma_m + b.sigma_m * b.sigma_m) / (dt_ab * dt_ab), bridged_var));
  history_.clear();
  trajectory_.clear();
  history_.push_back(entry);
  trajectory_.push_back(to_trajectory_sample(entry));
  // The anchors were de-skewed and placed on a guess: the next velocity
  // measurement spans two scans the IMU covered (header, 7).
  previous_registration_.reset();
  lidar_rate_i_rad_s_ = rate_i;
  anchor_.reset();
  previous_anchor_.reset();
  ++stats_.samples;
  ++stats_.reanchors;
  velocity_confirmed_ = false;
  restart_still_window();
  rests_to_check_.clear();
}

// A still window's velocity is final once no correction can rewrite it: the
// next correction rewrites from the middle of the interval since the newest
// registration (header, 3), so a window before that registration is final.
void ImuFuser::check_speeds_at_rest() {
  if (!previous_registration_) return;
  while (!rests_to_check_.empty() && rests_to_check_.front() < previous_registration_->t_s) {
    const double t_s = rests_to_check_.front();
    rests_to_check_.pop_front();
    if (t_s <= history_.front().t_s) continue;
    if (state_at(t_s).v_w.norm() > params_.max_speed_at_rest_m_s) {
      ++stats_.runaways_at_rest;
    } else {
      velocity_confirmed_ = true;
      rests_to_check_.clear();
    }
  }
}

void ImuFuser::restart_still_window() {
  static_count_ = 0;
  static_accel_sum_.setZero();
  static_gyro_sum_.setZero();
}

bool ImuFuser::completes_still_window(const ImuSample& sample, double duration_s) {
  const double accel_norm = sample.accel_m_s2.norm();
  bool moving = sample.gyro_rad_s.norm() > params_.static_max_gyro_rad_s ||
                std::abs(accel_norm - kStandardGravity_m_s2) > params_.static_accel_tolerance_m_s2 ||
                any(sample.accel_saturated) || any(sample.gyro_saturated);
  if (static_count_ > 0) {
    const Eigen::Vector3d mean = static_accel_sum_ / static_cast<double>(static_count_);
    moving = moving || (sample.accel_m_s2 - mean).norm() > params_.static_accel_tolerance_m_s2;
  }
  if (moving) {
    if (static_count_ > 0 && (!initialized_ || awaiting_rest_)) ++stats_.static_restarts;
    restart_still_window();
    return false;
  }
  if (static_count_ == 0) static_start_s_ = sample.t_s;
  ++static_count_;
  static_accel_sum_ += sample.accel_m_s2;
  static_gyro_sum_ += sample.gyro_rad_s;
  return static_count_ >= 2 && sample.t_s - static_start_s_ >= duration_s;
}

void ImuFuser::accumulate_static(const ImuSample& sample) {
  if (completes_still_window(sample, params_.static_duration_s)) initialize(sample);
}

void ImuFuser::restart_at_rest() {
  if (!initialized_) return;
  awaiting_rest_ = true;
  restart_still_window();
  previous_registration_.reset();
  anchor_.reset();
  previous_anchor_.reset();
  newest_levelling_s_.reset();  // the accelerometer is the only tilt reference until a map is registered on
  rests_to_check_.clear();
  ++stats_.restarts_at_rest;
}

void ImuFuser::add_imu_awaiting_rest(const ImuSample& sample, const HistoryEntry& previous) {
  HistoryEntry entry = measured_entry(sample);
  const double dt = sample.t_s - previous.t_s;
  if (!step_attitude(madgwick_, entry, dt)) ++stats_.accel_gated;
  entry.q_wi = madgwick_.orientation();
  entry.accel_w = gravity_free_accel(entry.q_wi, entry.accel_i);
  // The velocity is unknown, so the position is held rather than carried off by a guess.
  entry.state = previous.state;
  entry.state.v_w.setZero();
  entry.state.variance.setConstant(kUnknownVelocityVariance_m2_s2);
  if (completes_still_window(sample, params_.rest_duration_s)) end_wait_at_rest(entry);
  history_.push_back(entry);
  trajectory_.push_back(to_trajectory_sample(entry));
  ++stats_.samples;
}

void ImuFuser::end_wait_at_rest(HistoryEntry& entry) {
  const double count = static_cast<double>(static_count_);
  const Eigen::Vector3d mean_accel_i = static_accel_sum_ / count;
  gyro_bias_ = static_gyro_sum_ / count;
  // Still, the accelerometer points up: the smallest rotation that makes it
  // so levels the attitude and keeps the heading.
  const Eigen::Quaterniond level =
      Eigen::Quaterniond::FromTwoVectors(entry.q_wi * mean_accel_i, Eigen::Vector3d::UnitZ());
  entry.q_wi = (level * entry.q_wi).normalized();
  madgwick_.set_orientation(entry.q_wi);
  entry.gyro_clipped_i.setZero();
  entry.gyro_i.setZero();
  entry.accel_w = gravity_free_accel(entry.q_wi, entry.accel_i);
  entry.state.v_w.setZero();
  entry.state.variance.setConstant(params_.initial_velocity_sigma_m_s * params_.initial_velocity_sigma_m_s);
  entry.state.speed_unknown = {};
  awaiting_rest_ = false;
  velocity_confirmed_ = true;
  restart_still_window();
  ++stats_.rests;
}

void ImuFuser::initialize(const ImuSample& last_sample) {
  const double count = static_cast<double>(static_count_);
  const Eigen::Vector3d mean_accel = static_accel_sum_ / count;
  gyro_bias_ = static_gyro_sum_ / count;
  gravity_m_s2_ = mean_accel.norm();

  const Eigen::Quaterniond q_wl = levelled_lidar_attitude(q_li_ * mean_accel);
  const Eigen::Quaterniond q_wi = (q_wl * q_li_).normalized();
  madgwick_ = MadgwickFilter(params_.madgwick, q_wi, gravity_m_s2_);
  if (params_.attitude_from_device && last_sample.has_orientation) {
    device_alignment_ = q_wi * last_sample.orientation.conjugate();
  }

  HistoryEntry entry;
  entry.t_s = last_sample.t_s;
  entry.accel_i = last_sample.accel_m_s2;
  entry.gyro_clipped_i = last_sample.gyro_rad_s - gyro_bias_;
  entry.gyro_i = entry.gyro_clipped_i;
  entry.q_wi = q_wi;
  entry.accel_w = gravity_free_accel(q_wi, entry.accel_i);
  entry.state.p_w = q_wl * params_.T_li.translation();  // the lidar is at W's origin
  entry.state.variance.setConstant(params_.initial_velocity_sigma_m_s * params_.initial_velocity_sigma_m_s);
  history_.push_back(entry);
  trajectory_.push_back(to_trajectory_sample(entry));
  initialized_ = true;
}

std::size_t ImuFuser::entry_before(double t_s) const {
  std::size_t lo = 0, hi = history_.size() - 1;
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo + 1) / 2;
    if (history_[mid].t_s < t_s) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo;
}

ImuFuser::KinematicState ImuFuser::state_at(double t_s) const {
  if (t_s <= history_.front().t_s) return history_.front().state;
  const std::size_t j = entry_before(t_s);
  KinematicState state = history_[j].state;
  if (j + 1 < history_.size()) {
    const HistoryEntry& a = history_[j];
    const HistoryEntry& b = history_[j + 1];
    const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
    integrate(state, a.accel_w, a.accel_w + u * (b.accel_w - a.accel_w), t_s - a.t_s);
  }
  return state;
}

bool ImuFuser::accelerometer_levels(double t_s) const {
  return !(newest_levelling_s_ && t_s - *newest_levelling_s_ <= params_.accel_correction_after_s);
}

bool ImuFuser::step_attitude(MadgwickFilter& filter, const HistoryEntry& entry, double dt_s) const {
  // A clipped accelerometer is no gravity reference; otherwise the registrations level the attitude (header, 2).
  if (any(entry.accel_clipped) || !accelerometer_levels(entry.t_s)) {
    filter.propagate(entry.gyro_i, dt_s);
    return !any(entry.accel_clipped);
  }
  return filter.update(entry.gyro_i, entry.accel_i, dt_s);
}

Eigen::Quaterniond ImuFuser::attitude_at(double t_s) const {
  if (t_s <= history_.front().t_s) return history_.front().q_wi;
  const std::size_t j = entry_before(t_s);
  if (j + 1 >= history_.size()) return history_[j].q_wi;
  const HistoryEntry& a = history_[j];
  const HistoryEntry& b = history_[j + 1];
  return a.q_wi.slerp((t_s - a.t_s) / (b.t_s - a.t_s), b.q_wi);
}

CorrectionResult ImuFuser::correct_with_registered_pose(const ScanCorrection& scan) {
  CorrectionResult result;
  if (!takes_correction(scan)) return result;
  anchor_.reset();
  previous_anchor_.reset();
  check_speeds_at_rest();

  const RegisteredPose registered = registered_pose_of(scan);
  PoseReset reset;
  reset.t_s = scan.t_start_s;
  reset.t_scan_end_s = scan.t_end_s;
  reset.correction = (registered.q_wi * attitude_at(scan.t_start_s).conjugate()).normalized();
  reset.q_wi = registered.q_wi;
  reset.p_wi = registered.p_wi;
  if (!scan.map_start && (scan.expected_error_m <= params_.levelling_max_expected_error_m ||
                          scan.expected_rotation_error_rad <= params_.levelling_max_rotation_error_rad)) {
    newest_levelling_s_ = std::max(newest_levelling_s_.value_or(scan.t_start_s), scan.t_start_s);
  }
  const std::optional<VelocityMeasurement> velocity = velocity_from_registrations(scan, registered.q_wi, reset);

  const double t_first_event = velocity ? velocity->t_s : reset.t_s;
  result.rewritten_after_s = history_[entry_before(t_first_event)].t_s;
  repropagate(velocity, reset);
  previous_registration_ = registered;

  result.pose_reset = true;
  result.velocity_updated = velocity.has_value();
  ++stats_.pose_corrections;
  if (velocity) ++stats_.velocity_updates;
  return result;
}

// The IMU's pose the registered lidar pose gives, with the scan's uncertainty.
ImuFuser::RegisteredPose ImuFuser::registered_pose_of(const ScanCorrection& scan) const {
  return {scan.t_start_s,        scan.T_wl * params_.T_li.translation(),
          (Eigen::Quaterniond(scan.T_wl.rotation()) * q_li_).normalized(),
          scan.position_sigma_m, scan.unmeasured_w, scan.position_var_w_m2};
}

bool ImuFuser::takes_correction(const ScanCorrection& scan) {
  if (!initialized_) {
    ++stats_.corrections_before_init;
    return false;
  }
  if (awaiting_rest_) {
    ++stats_.corrections_awaiting_rest;
    return false;
  }
  if (scan.t_start_s > history_.back().t_s) {  // the IMU is silent: an anchor for when it returns (header, 7)
    if (!anchor_ || scan.t_start_s > anchor_->t_s) {
      previous_anchor_ = anchor_;
      anchor_ = registered_pose_of(scan);
      ++stats_.anchors_while_imu_silent;
      return false;
    }
  }
  if (!(scan.t_start_s > history_.front().t_s && scan.t_start_s <= history_.back().t_s)) {
    ++stats_.corrections_outside_history;
    return false;
  }
  return true;
}

std::optional<ImuFuser::VelocityMeasurement> ImuFuser::velocity_from_registrations(
    const ScanCorrection& scan, const Eigen::Quaterniond& q_wi_registered, PoseReset& reset) {
  if (scan.jumped) {
    // What the jump says the velocity may be wrong by, over the interval it closes (header, 8).
    const double interval_s =
        previous_registration_ ? std::max(scan.t_start_s - previous_registration_->t_s, 1e-3) : 0.1;
    const double jump_m = (reset.p_wi - state_at(scan.t_start_s).p_w).norm();
    reset.velocity_variance_floor_m2_s2 = (jump_m / interval_s) * (jump_m / interval_s);
    ++stats_.jumps;
    ++stats_.velocity_updates_skipped;
    return std::nullopt;
  }
  if (!previous_registration_) return std::nullopt;
  const RegisteredPose& previous = *previous_registration_;
  const double dt = scan.t_start_s - previous.t_s;
  if (dt <= 0.0 || dt > params_.max_lidar_interval_s || previous.t_s < history_.front().t_s) {
    ++stats_.velocity_updates_skipped;
    return std::nullopt;
  }
  const Eigen::Vector3d lidar_mean = (reset.p_wi - previous.p_wi) / dt;
  const Eigen::Vector3d filter_mean = (state_at(scan.t_start_s).v_integral - state_at(previous.t_s).v_integral) / dt;
  // Either end may be a prediction along its held direction: the interval
  // measures an axis only as well as both ends do (a held end that drifted
  // would otherwise pass its whole drift into the velocity at once).
  // Each end's variance per axis is at least its scan's own there: where
  // the prediction's prior held the pose, the interval confirms the
  // prediction's velocity and measures little.
  const auto end_variance_m2 = [](double sigma_m, const Eigen::Vector3d& var_w_m2) {
    return var_w_m2.cwiseMax(sigma_m * sigma_m);
  };
  const Eigen::Vector3d variance_m2 = end_variance_m2(scan.position_sigma_m, scan.position_var_w_m2) +
                                      end_variance_m2(previous.sigma_m, previous.var_w_m2);
  const double unmeasured_m2 = params_.unmeasured_position_sigma_m * params_.unmeasured_position_sigma_m;
  const Eigen::Vector3d unmeasured_per_axis_m2 =
      unmeasured_m2 * (scan.unmeasured_w.cwiseAbs2() + previous.unmeasured_w.cwiseAbs2());
  VelocityMeasurement velocity{previous.t_s + 0.5 * dt, lidar_mean - filter_mean,
                               (variance_m2 + unmeasured_per_axis_m2) / (dt * dt)};
  for (int i = 0; i < 3; ++i)
    velocity.measured[static_cast<std::size_t>(i)] = unmeasured_per_axis_m2[i] <= variance_m2[i];
  const Eigen::AngleAxisd turn((previous.q_wi.conjugate() * q_wi_registered).normalized());
  lidar_rate_i_rad_s_ = turn.angle() * turn.axis() / dt;
  return velocity;
}

void ImuFuser::repropagate(const std::optional<VelocityMeasurement>& velocity, const PoseReset& reset) {
  const double t_first_event = velocity ? velocity->t_s : reset.t_s;
  const std::size_t base = entry_before(t_first_event);
  KinematicState state = history_[base].state;
  double t = history_[base].t_s;
  Eigen::Vector3d accel_at_t = history_[base].accel_w;
  bool velocity_pending = velocity.has_value();
  bool reset_pending = true;
  trajectory_.truncate_after(t);
  // After the reset the attitude is rebuilt step by step (header, 2), the
  // newest lidar rate where the gyro was clipped. Up to the first sample at
  // or after the scan's end (where a lossless replay holds the fuser until
  // the registration is done): the gyro alone where the accelerometer is
  // left out, else Madgwick's step as taken. After it, each step is taken
  // again from the corrected attitude with the bits add_imu() uses, as if
  // the correction had come at that sample: a sample added after the
  // correction came gets the same bits as one rebuilt here. The device's
  // own attitude keeps its steps as taken.
  std::size_t scan_end = base + 1;
  while (scan_end + 1 < history_.size() && history_[scan_end].t_s < reset.t_scan_end_s) ++scan_end;
  AttitudeRebuild rebuild{.filter = madgwick_, .previous_q_before = std::nullopt, .previous_q_after = std::nullopt};

  for (std::size_t n = base + 1; n < history_.size(); ++n) {
    HistoryEntry& entry = history_[n];
    const double t_previous = t;
    const Eigen::Vector3d accel_previous = accel_at_t;
    if (entry.t_s >= reset.t_s) rebuild_attitude(n, scan_end, reset, rebuild);
    // Advances the state to an event time inside (t_previous, entry.t_s];
    // at the sample itself with its own acceleration, as add_imu() does
    // (a + (b − a) need not be b).
    auto advance_to = [&](double t_event) {
      const double u = (t_event - t_previous) / (entry.t_s - t_previous);
      const Eigen::Vector3d accel_event =
          t_event == entry.t_s ? entry.accel_w : Eigen::Vector3d(accel_previous + u * (entry.accel_w - accel_previous));
      integrate(state, accel_at_t, accel_event, t_event - t);
      t = t_event;
      accel_at_t = accel_event;
    };
    if (velocity_pending && velocity->t_s <= entry.t_s) {
      advance_to(velocity->t_s);
      update_velocity(state, *velocity);
      velocity_pending = false;
    }
    if (reset_pending && reset.t_s <= entry.t_s) {
      advance_to(reset.t_s);
      state.p_w = reset.p_wi;
      state.variance = state.variance.cwiseMax(reset.velocity_variance_floor_m2_s2);
      reset_pending = false;
      if (reset.t_s < entry.t_s) {  // the registered pose itself, between two IMU samples
        HistoryEntry anchor = entry;
        anchor.t_s = reset.t_s;
        anchor.q_wi = reset.q_wi;
        anchor.state = state;
        trajectory_.push_back(to_trajectory_sample(anchor));
      }
    }
    advance_to(entry.t_s);
    add_clip_noise(state, entry, entry.t_s - t_previous);
    entry.state = state;
    trajectory_.push_back(to_trajectory_sample(entry));
  }

  if (history_.size() - 1 <= scan_end) {
    madgwick_.set_orientation(history_.back().q_wi);
  } else {
    madgwick_.resume_from(history_.back().q_wi);
  }
  if (device_alignment_) device_alignment_ = (reset.correction * *device_alignment_).normalized();
}

// Entry n's attitude after the reset (header, 2), from the newest rebuilt
// one before it in `rebuild`.
void ImuFuser::rebuild_attitude(std::size_t n, std::size_t scan_end, const PoseReset& reset,
                                AttitudeRebuild& rebuild) {
  HistoryEntry& entry = history_[n];
  const Eigen::Quaterniond q_before = entry.q_wi;
  // The accelerometer may have stepped this sample before the correction
  // came; where it is left out, the gyro alone rebuilds it (header, 2).
  const bool gyro_alone = !params_.attitude_from_device && !accelerometer_levels(entry.t_s);
  if (!rebuild.previous_q_after) {
    entry.q_wi = gyro_alone && !any(entry.gyro_clipped)
                     ? integrate_body_rate(reset.q_wi, entry.gyro_i, entry.t_s - reset.t_s)
                     : (reset.correction * q_before).normalized();
  } else if (n > scan_end && !params_.attitude_from_device) {
    if (any(entry.gyro_clipped)) entry.gyro_i = unclipped_gyro(entry.gyro_clipped_i, entry.gyro_clipped);
    // The correction sets the filter (normalised) to the newest attitude
    // it finds, as at the end of repropagate(); add_imu() then steps on
    // from the filter's own output.
    if (n == scan_end + 1) {
      rebuild.filter.set_orientation(*rebuild.previous_q_after);
    } else {
      rebuild.filter.resume_from(*rebuild.previous_q_after);
    }
    step_attitude(rebuild.filter, entry, entry.t_s - history_[n - 1].t_s);
    entry.q_wi = rebuild.filter.orientation();
  } else if (any(entry.gyro_clipped) || gyro_alone) {
    if (any(entry.gyro_clipped)) entry.gyro_i = unclipped_gyro(entry.gyro_clipped_i, entry.gyro_clipped);
    entry.q_wi = integrate_body_rate(*rebuild.previous_q_after, entry.gyro_i, entry.t_s - history_[n - 1].t_s);
  } else {
    entry.q_wi = (*rebuild.previous_q_after * (rebuild.previous_q_before->conjugate() * q_before)).normalized();
  }
  rebuild.previous_q_before = q_before;
  rebuild.previous_q_after = entry.q_wi;
  entry.accel_w = gravity_free_accel(entry.q_wi, entry.accel_i);
}

// A Kalman update per W axis.
void ImuFuser::update_velocity(KinematicState& state, const VelocityMeasurement& velocity) {
  for (int i = 0; i < 3; ++i) {
    const double total = state.variance[i] + velocity.noise_variance[i];
    const double gain = total > 0.0 ? state.variance[i] / total : 0.0;
    state.v_w[i] += gain * velocity.innovation[i];
    state.variance[i] *= 1.0 - gain;
  }
  // A clipped axis's speed is known again once a scan measures it.
  for (std::size_t i = 0; i < 3; ++i) state.speed_unknown[i] = state.speed_unknown[i] && !velocity.measured[i];
}

TrajectorySample ImuFuser::to_trajectory_sample(const HistoryEntry& entry) const {
  TrajectorySample sample;
  sample.t_s = entry.t_s;
  sample.q_wl = (entry.q_wi * q_li_.conjugate()).normalized();
  sample.p_w = entry.state.p_w + entry.q_wi * p_il_;
  sample.v_w = entry.state.v_w + entry.q_wi * entry.gyro_i.cross(p_il_);
  sample.omega_l = q_li_ * entry.gyro_i;
  sample.velocity_var_w_m2_s2 = entry.state.variance;

  const Eigen::Matrix3d r_li = q_li_.toRotationMatrix();
  const Eigen::Matrix3d r_wl = sample.q_wl.toRotationMatrix();
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t j = 0; j < 3; ++j) {
      const auto row = static_cast<Eigen::Index>(k), col = static_cast<Eigen::Index>(j);
      if (entry.gyro_clipped[j] && std::abs(r_li(row, col)) > kAxisCoupling) sample.gyro_saturated[k] = true;
      // r_wl(j, k): lidar axis k along W axis j.
      if (entry.state.speed_unknown[j] && std::abs(r_wl(col, row)) > kAxisCoupling) sample.accel_saturated[k] = true;
    }
    sample.saturated[k] = sample.gyro_saturated[k] || sample.accel_saturated[k];
  }
  return sample;
}

}  // namespace tumble
