#include "drivers/mti/imu_sample.hpp"

#include <cmath>

namespace tumble::mti {
namespace {

// Rotation vector of an attitude increment divided by its period: the mean
// angular rate over the period.
Eigen::Vector3d rate_from_delta_q(const std::array<double, 4>& dq, double period_s) {
  double w = dq[0];
  Eigen::Vector3d v(dq[1], dq[2], dq[3]);
  if (w < 0) {  // q and -q are the same rotation; take the short way round
    w = -w;
    v = -v;
  }
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v / period_s;
  return (2.0 * std::atan2(s, w) / s) * v / period_s;
}

}  // namespace

bool has_imu_data(const MtData2& m) {
  return (m.acceleration_m_s2 && m.rate_of_turn_rad_s) || (m.delta_v_m_s && m.delta_q);
}

bool fill_imu_sample(const MtData2& m, double output_period_s, ImuSample& out) {
  if (m.acceleration_m_s2 && m.rate_of_turn_rad_s) {
    out.accel_m_s2 = *m.acceleration_m_s2;
    out.gyro_rad_s = *m.rate_of_turn_rad_s;
  } else if (m.delta_v_m_s && m.delta_q) {
    out.accel_m_s2 = *m.delta_v_m_s / output_period_s;
    out.gyro_rad_s = rate_from_delta_q(*m.delta_q, output_period_s);
  } else {
    return false;
  }
  const std::uint32_t status = m.status_word.value_or(0);  // StatusByte has no clip flags
  for (int axis = 0; axis < 3; ++axis) {
    out.accel_saturated[axis] = (status >> (kStatusClipAccelFirstBit + axis)) & 1u;
    out.gyro_saturated[axis] = (status >> (kStatusClipGyroFirstBit + axis)) & 1u;
  }
  out.has_orientation = m.quaternion.has_value();
  if (m.quaternion) {
    const auto& q = *m.quaternion;
    out.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  } else {
    out.orientation = Eigen::Quaterniond::Identity();
  }
  return true;
}

}  // namespace tumble::mti
