// The simulated MTi-30, checked through the project's own MTi decoder: ideal
// samples must integrate back to the trajectory, clipping must be flagged as
// the device does, and the serial stream must look like a tty's reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/imu_sample.hpp"
#include "drivers/mti/mtdata2_decode.hpp"
#include "drivers/mti/mti_stream.hpp"
#include "drivers/pcap/pcap_file.hpp"
#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/imu_stream.hpp"

namespace tumble::sim {
namespace {

using test::SpinMotion;
using test::TempDir;
using test::WobbleMotion;

constexpr double kDegToRad = std::numbers::pi / 180.0;

struct DecodedFrame {
  mti::MtData2 message;
  ImuSample sample;
  std::size_t read_index = 0;  // the read that delivered the frame's last byte
};

struct DecodedStream {
  std::vector<DecodedFrame> frames;
  std::vector<std::uint8_t> control_mids;
  std::vector<SerialRead> reads;
  mti::FrameReaderStats reader_stats;
};

// The reads go through an IMU pcap (as written to disk) and the driver's
// frame reader and MTData2 decoder.
DecodedStream decode(ImuStream& stream, double output_period_s) {
  TempDir dir;
  const auto path = (dir.path() / "imu.pcap").string();
  {
    pcap::Writer writer(path, pcap::kLinkUser0);
    SerialRead read;
    while (stream.next(read)) writer.write(read.arrival_ns, read.bytes);
  }
  DecodedStream out;
  pcap::Reader reader(path);
  EXPECT_EQ(reader.link_type(), pcap::kLinkUser0);
  mti::FrameReader frames;
  mti::MtData2DecodeStats stats;
  while (const auto record = reader.next()) {
    out.reads.push_back({record->t_ns, std::vector<std::uint8_t>(record->bytes.begin(), record->bytes.end())});
    frames.push(out.reads.back().bytes);
    while (const auto frame = frames.next()) {
      if (frame->mid != 0x36) {
        out.control_mids.push_back(frame->mid);
        continue;
      }
      DecodedFrame f;
      EXPECT_TRUE(mti::decode_mtdata2(frame->payload, f.message, stats));
      EXPECT_TRUE(mti::fill_imu_sample(f.message, output_period_s, f.sample));
      f.read_index = out.reads.size() - 1;
      out.frames.push_back(f);
    }
  }
  out.reader_stats = frames.stats();
  return out;
}

ImuClock clock_at(double first_sample_s, double drift_ppm = 0.0, std::uint32_t first_ticks = 1'234'500) {
  ImuClock c;
  c.first_sample_s = first_sample_s;
  c.drift_ppm = drift_ppm;
  c.first_sample_time_fine = first_ticks;
  c.first_packet_counter = 65530;  // wraps during the test
  return c;
}

// State of the IMU frame in W.
struct ImuState {
  Eigen::Quaterniond q_wi;
  Eigen::Vector3d v_w, p_w;
};

ImuState true_imu_state(const Motion& motion, const Eigen::Isometry3d& T_LI, double t) {
  const MotionState s = motion.at(t);
  const Eigen::Matrix3d R_wb = s.T_wb.linear();
  const Eigen::Vector3d& r = T_LI.translation();
  return {Eigen::Quaterniond(R_wb * T_LI.linear()), s.v_w + R_wb * s.omega_b.cross(r), s.T_wb * r};
}

struct Derivative {
  Eigen::Quaterniond q_dot;  // as 4 numbers
  Eigen::Vector3d v_dot, p_dot;
};

Derivative derivative(const ImuState& x, const Eigen::Vector3d& f_i, const Eigen::Vector3d& w_i) {
  const Eigen::Quaterniond dq = x.q_wi * Eigen::Quaterniond(0.0, w_i.x(), w_i.y(), w_i.z());
  return {Eigen::Quaterniond(0.5 * dq.coeffs()), x.q_wi * f_i + Eigen::Vector3d(0, 0, -kStandardGravity_m_s2), x.v_w};
}

ImuState advance(const ImuState& x, const Derivative& d, double h) {
  return {Eigen::Quaterniond(x.q_wi.coeffs() + h * d.q_dot.coeffs()), x.v_w + h * d.v_dot, x.p_w + h * d.p_dot};
}

TEST(ImuModel, IdealSamplesIntegrateBackToTheTrajectory) {
  const WobbleMotion motion(1.3, {0.3, 0.2, 0.1}, {3.0, 4.0, 5.0}, 0.8, 6.0, {0.3, 0.5, 0.8});
  const Eigen::Isometry3d T_LI = pose_from_xyz_rpy_deg({0.05, -0.03, -0.12}, {10.0, -5.0, 90.0});
  ImuConfig config;
  config.rate_hz = 400;
  ImuLinkConfig link;
  link.baud = 921600;
  const ImuClock clock = clock_at(0.00123);
  ImuStream stream(config, clock, link, T_LI, motion, 1, false, 1.25);
  const DecodedStream decoded = decode(stream, 1.0 / config.rate_hz);
  ASSERT_GE(decoded.frames.size(), 401u);

  // Sample times from SampleTimeFine (no drift here), as a driver would.
  const auto t_of = [&](const DecodedFrame& f) {
    return clock.first_sample_s + (*f.message.sample_time_fine - clock.first_sample_time_fine) / 10'000.0;
  };
  ImuState x = true_imu_state(motion, T_LI, t_of(decoded.frames[0]));
  double worst_position_m = 0, worst_angle_deg = 0;
  // RK4 over pairs of samples: k, k+1 (the midpoint), k+2.
  for (std::size_t k = 0; k + 2 <= 400; k += 2) {
    const double h = t_of(decoded.frames[k + 2]) - t_of(decoded.frames[k]);
    const auto& s0 = decoded.frames[k].sample;
    const auto& s1 = decoded.frames[k + 1].sample;
    const auto& s2 = decoded.frames[k + 2].sample;
    const Derivative k1 = derivative(x, s0.accel_m_s2, s0.gyro_rad_s);
    const Derivative k2 = derivative(advance(x, k1, h / 2), s1.accel_m_s2, s1.gyro_rad_s);
    const Derivative k3 = derivative(advance(x, k2, h / 2), s1.accel_m_s2, s1.gyro_rad_s);
    const Derivative k4 = derivative(advance(x, k3, h), s2.accel_m_s2, s2.gyro_rad_s);
    x.q_wi.coeffs() += h / 6 * (k1.q_dot.coeffs() + 2 * k2.q_dot.coeffs() + 2 * k3.q_dot.coeffs() + k4.q_dot.coeffs());
    x.q_wi.normalize();
    x.v_w += h / 6 * (k1.v_dot + 2 * k2.v_dot + 2 * k3.v_dot + k4.v_dot);
    x.p_w += h / 6 * (k1.p_dot + 2 * k2.p_dot + 2 * k3.p_dot + k4.p_dot);
    const ImuState truth = true_imu_state(motion, T_LI, t_of(decoded.frames[k + 2]));
    worst_position_m = std::max(worst_position_m, (x.p_w - truth.p_w).norm());
    worst_angle_deg = std::max(worst_angle_deg, x.q_wi.angularDistance(truth.q_wi) / kDegToRad);
  }
  // Over 1 s of 0.3 m / 4.8 rad/s motion with a lever arm and a rotated mount.
  EXPECT_LT(worst_position_m, 1e-3);
  EXPECT_LT(worst_angle_deg, 0.01);
  // And the travel was large enough for a wrong lever arm or gravity to show.
  EXPECT_GT((true_imu_state(motion, T_LI, 1.0).p_w - true_imu_state(motion, T_LI, 0.0).p_w).norm(), 0.1);
}

TEST(ImuModel, ClippingHoldsTheRangeLimitAndSetsTheStatusBits) {
  // Gyro: a 10 rad/s spin about z (the range is 450 deg/s = 7.85 rad/s).
  const SpinMotion spin({0, 0, 1}, 10.0, 0.2);
  ImuStream gyro_stream(ImuConfig{}, clock_at(0.0), ImuLinkConfig{}, Eigen::Isometry3d::Identity(), spin, 1, false, 0.2);
  const DecodedStream gyro = decode(gyro_stream, 0.01);
  ASSERT_GE(gyro.frames.size(), 20u);
  for (const auto& f : gyro.frames) {
    EXPECT_EQ(*f.message.status_word, (1u << 13) | (1u << 19));
    EXPECT_NEAR(f.sample.gyro_rad_s.z(), 450.0 * kDegToRad, 1e-6);
    EXPECT_EQ(f.sample.gyro_saturated, (std::array<bool, 3>{false, false, true}));
    EXPECT_EQ(f.sample.accel_saturated, (std::array<bool, 3>{false, false, false}));
  }

  // Accelerometer: 0.1 m at 50 rad/s along x peaks at 250 m/s^2 (range 200).
  // Each 10 kHz sub-sample is clipped, the period's mean is reported, and the
  // flag says some sub-sample was clipped.
  const WobbleMotion shake(0.3, {0.1, 0.0, 0.0}, {50.0, 1.0, 1.0}, 0.0, 1.0, {0, 0, 1});
  ImuConfig config;
  ImuModel model(config, clock_at(0.0005), Eigen::Isometry3d::Identity(), shake, 1, false);
  ImuMeasurement m;
  int clipped = 0, unclipped = 0;
  while (model.next(0.3, m)) {
    // The period around the sample, finer than the device samples it.
    constexpr int kFine = 1000;
    double clipped_mean = 0.0, peak = 0.0;
    for (int j = 0; j < kFine; ++j) {
      const double t = m.t_s + 0.01 * ((j + 0.5) / kFine - 0.5);
      const double f = imu_kinematics(shake.at(t), Eigen::Isometry3d::Identity()).specific_force_i.x();
      clipped_mean += std::clamp(f, -200.0, 200.0) / kFine;
      peak = std::max(peak, std::abs(f));
    }
    EXPECT_NEAR(m.accel_m_s2.x(), clipped_mean, 0.05) << "t " << m.t_s;
    EXPECT_LE(std::abs(m.accel_m_s2.x()), 200.0);
    if (peak > 200.5) {
      ++clipped;
      EXPECT_EQ(m.status_word, (1u << 8) | (1u << 19)) << "t " << m.t_s;
    } else if (peak < 199.5) {
      ++unclipped;
      EXPECT_EQ(m.status_word, 0u) << "t " << m.t_s;
    }
  }
  EXPECT_GT(clipped, 3);
  EXPECT_GT(unclipped, 3);
}

// A body at rest whose velocity along W x makes one smooth excursion of
// `excursion_m_s` over `duration_s` from `start_s`: out and back (net change
// zero, a jolt) or out and staying (net change excursion_m_s, a step).
// The IMU reads only its acceleration (no rotation, so no position needed).
class VelocityExcursion final : public Motion {
 public:
  VelocityExcursion(double start_s, double duration_s, double excursion_m_s, bool returns)
      : start_(start_s), duration_(duration_s), excursion_(excursion_m_s), returns_(returns) {}
  MotionState at(double t) const override {
    MotionState s;
    const double u = std::clamp((t - start_) / duration_, 0.0, 1.0);
    const double inside = u > 0.0 && u < 1.0 ? 1.0 : 0.0;
    const double pi = std::numbers::pi;
    if (returns_) {  // v = V sin²(π u)
      s.v_w.x() = excursion_ * std::sin(pi * u) * std::sin(pi * u);
      s.a_w.x() = inside * excursion_ * pi / duration_ * std::sin(2 * pi * u);
    } else {  // v = V (1 − cos(π u)) / 2
      s.v_w.x() = excursion_ * (1.0 - std::cos(pi * u)) / 2;
      s.a_w.x() = inside * excursion_ * pi / (2 * duration_) * std::sin(pi * u);
    }
    return s;
  }
  double duration_s() const override { return 1.0; }

 private:
  double start_, duration_, excursion_;
  bool returns_;
};

TEST(ImuModel, AnImpactShorterThanThePeriodReadsAsItsNetVelocityChange) {
  // A 4 ms jolt peaking at 196 m/s² (the rolling cage's) around the sample
  // at 0.51 s: sampled at that instant it would read -194 m/s² for the whole
  // 10 ms period, 1.9 m/s of velocity the body never had. Periods are
  // centred on the samples: [0.505, 0.515] holds it whole; from 0.5031 it
  // straddles 0.505, its first lobe in one period and its second in the next.
  for (const double start_s : {0.5071, 0.5031}) {
    for (const bool returns : {true, false}) {
      const VelocityExcursion motion(start_s, 0.004, 0.25, returns);
      ImuModel model(ImuConfig{}, clock_at(0.0), Eigen::Isometry3d::Identity(), motion, 1, false);
      ImuMeasurement m;
      double delta_v_m_s = 0.0, largest_m_s2 = 0.0;
      while (model.next(1.0, m)) {
        delta_v_m_s += m.accel_m_s2.x() * 0.01;
        largest_m_s2 = std::max(largest_m_s2, std::abs(m.accel_m_s2.x()));
      }
      const std::string what = std::string(returns ? "jolt" : "step") + " from " + std::to_string(start_s);
      EXPECT_NEAR(delta_v_m_s, returns ? 0.0 : 0.25, 1e-4) << what;
      // What is read is the velocity change within each period, over the
      // period: at most 0.25 m/s / 10 ms (midpoint rule: 25.1).
      EXPECT_LT(largest_m_s2, 25.1) << what;
    }
  }
}

TEST(ImuModel, SampleTimeFineRunsOnTheDriftingDeviceClockAndWraps) {
  const SpinMotion still({0, 0, 1}, 0.0, 1.0);
  const ImuClock clock = clock_at(0.004, 10.0, 863'999'500);
  ImuModel model(ImuConfig{}, clock, Eigen::Isometry3d::Identity(), still, 1, false);
  ImuMeasurement m;
  std::vector<ImuMeasurement> samples;
  while (model.next(1.0, m)) samples.push_back(m);
  ASSERT_EQ(samples.size(), 100u);  // 0.004 + 99 * 0.01 / (1 + 1e-5) <= 1 s
  for (std::size_t k = 0; k < samples.size(); ++k) {
    EXPECT_EQ(samples[k].sample_time_fine, (863'999'500u + 100u * k) % 864'000'000u);
    EXPECT_EQ(samples[k].packet_counter, static_cast<std::uint16_t>(65530 + k));
    EXPECT_NEAR(samples[k].t_s, 0.004 + k * 0.01 / (1.0 + 10e-6), 1e-12);
  }
  EXPECT_EQ(samples[5].sample_time_fine, 0u);
}

TEST(ImuModel, NoiseAndBiasFollowTheDatasheet) {
  const SpinMotion still({0, 0, 1}, 0.0, 20.0);
  ImuConfig config;
  config.gyro_bias_stability_deg_h = 0.0;
  config.accel_bias_stability_ug = 0.0;
  ImuModel model(config, clock_at(0.0), Eigen::Isometry3d::Identity(), still, 9, true);
  ImuMeasurement m;
  Eigen::Vector3d gyro_sum = Eigen::Vector3d::Zero(), accel_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_sq = Eigen::Vector3d::Zero(), accel_sq = Eigen::Vector3d::Zero();
  int n = 0;
  const Eigen::Vector3d gravity_up(0, 0, kStandardGravity_m_s2);
  while (model.next(19.995, m)) {
    const Eigen::Vector3d g = m.gyro_rad_s - model.initial_gyro_bias_rad_s();
    const Eigen::Vector3d a = m.accel_m_s2 - gravity_up - model.initial_accel_bias_m_s2();
    gyro_sum += g;
    accel_sum += a;
    gyro_sq += g.cwiseProduct(g);
    accel_sq += a.cwiseProduct(a);
    ++n;
  }
  ASSERT_EQ(n, 2000);
  // White noise of density N at 100 Hz: sigma = N * 10.
  const double gyro_sigma = 0.03 * kDegToRad * 10.0, accel_sigma = 60e-6 * kStandardGravity_m_s2 * 10.0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(std::sqrt(gyro_sq[i] / n), gyro_sigma, 0.08 * gyro_sigma);
    EXPECT_NEAR(std::sqrt(accel_sq[i] / n), accel_sigma, 0.08 * accel_sigma);
    EXPECT_NEAR(gyro_sum[i] / n, 0.0, 4 * gyro_sigma / std::sqrt(n));
  }
  // The turn-on bias is drawn (0.2 deg/s, 1 sigma): not zero.
  EXPECT_GT(model.initial_gyro_bias_rad_s().norm(), 1e-4);
}

TEST(ImuStream, ReadsCarryEveryByteLikeATtyAtTheBaudRate) {
  const SpinMotion still({0, 0, 1}, 0.0, 1.0);
  ImuLinkConfig link;
  link.leading_garbage_bytes = 7;
  link.leading_config_ack = true;
  const ImuClock clock = clock_at(0.0031);
  ImuStream stream(ImuConfig{}, clock, link, Eigen::Isometry3d::Identity(), still, 3, true, 1.0);
  const DecodedStream d = decode(stream, 0.01);

  EXPECT_EQ(d.frames.size(), 100u);
  EXPECT_EQ(d.reader_stats.bytes_discarded, 7u);  // the capture began mid-frame
  EXPECT_EQ(d.control_mids, std::vector<std::uint8_t>{0x11});
  std::set<std::size_t> sizes;
  std::int64_t previous = -1;
  for (const auto& r : d.reads) {
    sizes.insert(r.bytes.size());
    EXPECT_GT(r.arrival_ns, previous);
    previous = r.arrival_ns;
  }
  EXPECT_GE(sizes.size(), 5u);  // reads of many sizes, not one per frame
  std::size_t split_frames = 0;
  const double byte_s = 10.0 / link.baud;
  for (std::size_t k = 0; k < d.frames.size(); ++k) {
    const auto& f = d.frames[k];
    EXPECT_EQ(*f.message.packet_counter, static_cast<std::uint16_t>(65530 + k));
    const double sample_s = clock.first_sample_s + k * 0.01;
    // The last byte cannot be read before it has crossed the wire.
    const double earliest_s = sample_s + link.processing_latency_s + 54 * byte_s;
    EXPECT_GE(d.reads[f.read_index].arrival_ns * 1e-9, earliest_s - 1e-9);
    EXPECT_LT(d.reads[f.read_index].arrival_ns * 1e-9, earliest_s + 0.01);
    split_frames += d.reads[f.read_index].bytes.size() < 54;
  }
  EXPECT_GT(split_frames, 5u);  // frames cut across reads
}

TEST(ImuStream, FrameSizeFitsTheBaudChecks) {
  EXPECT_EQ(mtdata2_frame_bytes(mti::NumberFormat::Float32), 54u);
  EXPECT_GT(mtdata2_frame_bytes(mti::NumberFormat::Float64), 54u);
}

// The simulated rig's lidar-IMU time offset (extrinsics.imu_time_offset_s)
// follows tumbled's imu.imu_time_offset_s: the same value in tumbled.yaml
// cancels it. Checked on the model (what a sample measures) and through the
// driver's byte stream (what tumbled makes of it).
const WobbleMotion kOffsetMotion(2.0, {0.2, 0.1, 0.1}, {3.0, 4.0, 5.0}, 0.8, 6.0, {0.3, 0.5, 0.8});
const Eigen::Isometry3d kOffsetT_LI = pose_from_xyz_rpy_deg({0.0, 0.03, -0.08}, {180.0, 0.0, 90.0});

ImuClock clock_with_offset(double imu_time_offset_s) {
  ImuClock c;
  c.first_sample_s = 0.1;
  c.first_sample_time_fine = 40'000;
  c.imu_time_offset_s = imu_time_offset_s;
  return c;
}

TEST(ImuTimeOffset, ASampleMeasuresTheMotionAtItsTimePlusTheOffset) {
  ImuModel model(ImuConfig{}, clock_with_offset(0.04), kOffsetT_LI, kOffsetMotion, 1, false);
  ImuMeasurement m;
  int checked = 0;
  while (model.next(1.5, m)) {
    // The rate is the mean over the 10 ms period around t + offset: about
    // the motion's fixed axis, the tilt angle's change over it divided by it.
    const auto tilt_rad = [](double t) { return Eigen::AngleAxisd(kOffsetMotion.at(t).T_wb.linear()).angle(); };
    const Eigen::Vector3d axis_i = kOffsetT_LI.linear().transpose() * Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
    const Eigen::Vector3d at_offset = axis_i * (tilt_rad(m.t_s + 0.045) - tilt_rad(m.t_s + 0.035)) / 0.01;
    const Eigen::Vector3d at_send = imu_kinematics(kOffsetMotion.at(m.t_s), kOffsetT_LI).omega_i;
    EXPECT_LT((m.gyro_rad_s - at_offset).norm(), 1e-5) << "t " << m.t_s;
    if ((at_offset - at_send).norm() > 0.05) ++checked;  // the offset is visible here
  }
  EXPECT_GT(checked, 50);
}

// The driver stamps a sample when its bytes arrive, less their time on the
// wire; the device's processing latency is not visible to it (here 0, so the
// stamp is the send time up to the read latency).
std::vector<ImuSample> decoded(double sim_offset_s, double tumbled_offset_s) {
  ImuLinkConfig link;
  link.processing_latency_s = 0.0;
  link.read_latency_s = 0.0;
  link.read_jitter_s = 0.0;
  ImuStream stream(ImuConfig{}, clock_with_offset(sim_offset_s), link, kOffsetT_LI, kOffsetMotion, 1, false, 1.9);
  mti::MtiStreamOptions options;
  options.imu_time_offset_s = tumbled_offset_s;
  mti::MtiStream driver(options);
  std::vector<ImuSample> out;
  SerialRead read;
  while (stream.next(read)) driver.feed(read.bytes, static_cast<double>(read.arrival_ns) * 1e-9, out);
  return out;
}

// Largest gap between what the samples read and the motion at their stamps.
double worst_rate_error_rad_s(const std::vector<ImuSample>& samples) {
  double worst = 0;
  for (const ImuSample& s : samples)
    worst = std::max(worst, (s.gyro_rad_s - imu_kinematics(kOffsetMotion.at(s.t_s), kOffsetT_LI).omega_i).norm());
  return worst;
}

TEST(ImuTimeOffset, TumbledsOffsetOfTheSameValueCancelsIt) {
  for (const double offset_s : {0.03, -0.03}) {
    const std::vector<ImuSample> cancelled = decoded(offset_s, offset_s);
    const std::vector<ImuSample> ignored = decoded(offset_s, 0.0);
    const std::vector<ImuSample> doubled = decoded(offset_s, -offset_s);
    ASSERT_GT(cancelled.size(), 150u);
    // 0.03 s at these rates and accelerations is ~0.2 rad/s; what is left
    // after cancelling is the quantised stamp (float32 rates, µs times).
    EXPECT_LT(worst_rate_error_rad_s(cancelled), 0.01) << offset_s;
    EXPECT_GT(worst_rate_error_rad_s(ignored), 0.1) << offset_s;
    EXPECT_GT(worst_rate_error_rad_s(doubled), worst_rate_error_rad_s(ignored)) << offset_s;
  }
}

}  // namespace
}  // namespace tumble::sim
