// Fuzzes the daemon layer the way `tumbled --replay --rate max` runs it: the
// input becomes a lidar pcap and an IMU pcap (in memory), which run_daemon
// replays through the real parts (make_sensor_parts: the replay sources, the
// lidar decoder and its choice of sender, the MTi decoder, the fuser and the
// registration stage with scan assembly, on the pipeline's threads) and
// publishes on memq:// LCM. Every TUMBLE_ODOM and TUMBLE_POSE message
// published while TUMBLE_STATUS says tracking must be finite, and each one a
// subscriber may trust (docs/lcm-interface.md, "What a subscriber must
// check") no farther from the trusted one before it than any motion can
// carry it; a thread failing ends the run with exit code 1, which is a crash
// here too. TUMBLE_FUZZ_DAEMON_VERBOSE=1 logs the run and prints what it
// published.
//
// The input is a list of operations, each introduced by a selector byte
// (selector % 8), on a data clock that starts at kStart_s:
//   0-3 move: [steps][yaw rate][speed][flags] for `steps` + 1 IMU periods,
//       the sensor turning at int8(yaw rate) * 0.05 rad/s about its vertical
//       axis and moving at int8(speed) * 0.02 m/s along its forward axis at
//       the start of the move, inside a box-shaped room: the MTi's frames
//       (MTData2, 100 Hz) and the RS-16's MSOP packets (600 rpm) it would
//       send, plus a DIFOP each second. Flags: bit 0 a second host sends
//       the same packets too (bit 5: as seen from 1 m further along x),
//       bit 1 the motor stalls with the lasers firing on, bit 2 the IMU is
//       silent, bit 3 the lidar is silent.
//   4   serial bytes: [n][n bytes] as one read; n = 0: one MTData2 frame
//       whose acceleration and rate of turn are the next 24 bytes as floats
//       (NaN, Inf, beyond the device's range).
//   5   raw datagram: [flags][length: 2 bytes][bytes]; flags bits 0-1 the
//       sender (the lidar, host B, host C, the lidar from another port),
//       bits 2-3 the destination port (MSOP, DIFOP, another, MSOP).
//   6   framed datagram: [flags][bytes]: the next bytes (up to a packet)
//       between the right magic and tail, MSOP with a valid advancing time
//       and block flags; flags bit 0 DIFOP, bits 1-2 the sender as above.
//   7   arrival time: [int8] the clock jumps by int8 * 0.05 s (back: the
//       records are written in operation order all the same).
// Data beyond kMaxData_s is not written: longer runs only slow the fuzzer.
//
// At exit it prints how deep the inputs got: how many published a
// registered scan and a trusted pose while tracking.
#include <sys/mman.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <span>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "daemon/config.hpp"
#include "daemon/main_loop.hpp"
#include "daemon/run.hpp"
#include "daemon/sensor_parts.hpp"
#include "drivers/mti/imu_recording_writer.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "drivers/mti/xbus_frame.hpp"
#include "drivers/pcap/udp_frame.hpp"
#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/laser_geometry.hpp"
#include "drivers/rs16/msop_encode.hpp"
#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/recording_writer.hpp"
#include "drivers/rs16/utc_time.hpp"
#include "tumble/odometry_t.hpp"
#include "tumble/registration_t.hpp"
#include "tumble/status_t.hpp"

namespace {

using namespace tumble;

constexpr double kStart_s = 1.7e9;
constexpr double kMaxData_s = 2.0;
constexpr double kImuPeriod_s = 0.01;
constexpr double kGravity_m_s2 = 9.81;
constexpr double kFiring_s = 55.5e-6;                  // one firing sequence of the 16 lasers
constexpr double kPacket_s = 12 * 2 * kFiring_s;      // 12 blocks of two sequences
constexpr double kSpin_deg_s = 3600.0;                 // 600 rpm
constexpr double kBlockStep_deg = kSpin_deg_s * 2 * kFiring_s;
constexpr std::uint32_t kLidarIp = 0xC0A801C8;  // 192.168.1.200
constexpr std::uint32_t kHostIp = 0xC0A80166;
constexpr std::array<std::uint32_t, 3> kSenderIps{kLidarIp, 0xC0A80132, 0x0A000005};
constexpr std::array<std::uint16_t, 4> kDstPorts{6699, 7788, 5353, 6699};

// The room: an axis-aligned box around the start, not symmetric, so that
// scans pin every direction.
const Eigen::Vector3d kRoomMin(-3.0, -2.5, -1.2);
const Eigen::Vector3d kRoomMax(5.0, 3.5, 2.0);

// Metres from `origin` along unit `direction` to the room's wall (origin inside).
double distance_to_wall(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  double t = 1e9;
  for (int i = 0; i < 3; ++i) {
    if (direction[i] > 1e-12) t = std::min(t, (kRoomMax[i] - origin[i]) / direction[i]);
    if (direction[i] < -1e-12) t = std::min(t, (kRoomMin[i] - origin[i]) / direction[i]);
  }
  return std::max(t, 0.0);
}

class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool done() const { return at_ >= size_; }
  std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }
  std::span<const std::uint8_t> bytes(std::size_t n) {
    n = std::min(n, size_ - at_);
    const std::span<const std::uint8_t> out(data_ + at_, n);
    at_ += n;
    return out;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

std::int64_t to_ns(double t_s) { return std::llround(t_s * 1e9); }

// Writes the two recordings tumbled replays, as the recorder and tumble-sim write them.
class Recordings {
 public:
  Recordings(const std::string& lidar_path, const std::string& imu_path) : lidar_(lidar_path), imu_(imu_path) {}

  void run(Input& in) {
    while (!in.done() && t_s_ < kStart_s + kMaxData_s) {
      const std::uint8_t op = in.byte() % 8;
      if (op < 4) {
        move(in);
      } else if (op == 4) {
        serial(in);
      } else if (op == 5) {
        raw_datagram(in);
      } else if (op == 6) {
        framed_datagram(in);
      } else {
        t_s_ += static_cast<std::int8_t>(in.byte()) * 0.05;
      }
    }
    lidar_.close();
    imu_.close();
  }

 private:
  void move(Input& in) {
    const int steps = in.byte() + 1;
    const double yaw_rate_rad_s = static_cast<std::int8_t>(in.byte()) * 0.05;
    const double speed_m_s = static_cast<std::int8_t>(in.byte()) * 0.02;
    const std::uint8_t flags = in.byte();
    const Eigen::Vector3d velocity_w = Eigen::AngleAxisd(yaw_rad_, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX() * speed_m_s;
    for (int k = 0; k < steps && t_s_ < kStart_s + kMaxData_s; ++k) {
      if ((flags & 4) == 0) imu_frame(Eigen::Vector3d(0, 0, kGravity_m_s2), Eigen::Vector3d(0, 0, yaw_rate_rad_s));
      const double end_s = t_s_ + kImuPeriod_s;
      while (next_packet_s_ < end_s) {
        const double dt_s = next_packet_s_ - t_s_;
        if ((flags & 8) == 0) lidar_packet(position_w_ + velocity_w * dt_s, yaw_rad_ + yaw_rate_rad_s * dt_s,
                                           yaw_rate_rad_s, (flags & 2) != 0, flags);
        next_packet_s_ += kPacket_s;
      }
      position_w_ += velocity_w * kImuPeriod_s;
      // Stay in the room: bounce off a wall (a velocity change the IMU does not see, as a fuzzer may do).
      for (int i = 0; i < 2; ++i) position_w_[i] = std::clamp(position_w_[i], kRoomMin[i] + 0.5, kRoomMax[i] - 0.5);
      yaw_rad_ += yaw_rate_rad_s * kImuPeriod_s;
      t_s_ = end_s;
    }
    next_packet_s_ = std::max(next_packet_s_, t_s_);
  }

  void imu_frame(const Eigen::Vector3d& accel_m_s2, const Eigen::Vector3d& gyro_rad_s) {
    mti::MtData2Out m;
    m.packet_counter = packet_counter_++;
    sample_time_fine_ += 100;
    m.sample_time_fine = sample_time_fine_;
    m.accel_m_s2 = accel_m_s2;
    m.gyro_rad_s = gyro_rad_s;
    imu_.write(to_ns(t_s_ + 0.002), mti::encode_xbus_frame(mti::mid::kMtData2, mti::encode_mtdata2(m)));
  }

  void lidar_packet(const Eigen::Vector3d& position_w, double yaw_rad, double yaw_rate_rad_s, bool stalled,
                    std::uint8_t flags) {
    const double t_s = next_packet_s_;
    if (t_s >= next_difop_s_) {
      rs16::DifopData difop;
      difop.vertical_angles_deg = rs16::kDesignVerticalAnglesDeg;
      const auto packet = rs16::encode_difop(difop);
      lidar_.write(to_ns(t_s), rs16::PacketKind::Difop, packet);
      next_difop_s_ = t_s + 1.0;
    }
    const auto msop = room_packet(position_w, yaw_rad, yaw_rate_rad_s, stalled, t_s);
    lidar_.write(to_ns(t_s), rs16::PacketKind::Msop, msop);
    if ((flags & 1) != 0) {
      const auto echo = (flags & 32) == 0 ? msop
                                          : room_packet(position_w + Eigen::Vector3d(1.0, 0, 0), yaw_rad,
                                                        yaw_rate_rad_s, stalled, t_s);
      lidar_.write_from(kSenderIps[1], to_ns(t_s + 1e-4), rs16::PacketKind::Msop, echo);
    }
    if (!stalled) azimuth_deg_ = std::fmod(azimuth_deg_ + 12 * kBlockStep_deg, 360.0);
  }

  std::array<std::uint8_t, rs16::kPacketSize> room_packet(const Eigen::Vector3d& position_w, double yaw_rad,
                                                          double yaw_rate_rad_s, bool stalled, double t_s) const {
    rs16::MsopPacketData p;
    p.utc_time_ns = to_ns(t_s);
    for (int b = 0; b < 12; ++b) {
      const double block_az_deg = azimuth_deg_ + (stalled ? 0.0 : b * kBlockStep_deg);
      p.blocks[b].azimuth_deg = std::fmod(block_az_deg, 360.0);
      for (int sequence = 0; sequence < 2; ++sequence) {
        const double az = (block_az_deg + (sequence == 0 || stalled ? 0.0 : kBlockStep_deg / 2)) * M_PI / 180;
        // The beam's horizontal direction in W: the azimuth turns clockwise seen from above (y = -sin).
        const double heading = yaw_rad + yaw_rate_rad_s * (2 * b + sequence) * kFiring_s - az;
        const double cos_h = std::cos(heading);
        const double sin_h = std::sin(heading);
        const Eigen::Vector3d centre_w =
            position_w + rs16::kOpticalCentreOffset_m * Eigen::Vector3d(cos_h, sin_h, 0.0);
        for (int laser = 0; laser < 16; ++laser) {
          const Eigen::Vector3d direction_w(cos_vertical_[laser] * cos_h, cos_vertical_[laser] * sin_h,
                                            sin_vertical_[laser]);
          p.blocks[b].channels[sequence * 16 + laser] = {distance_to_wall(centre_w, direction_w), 100};
        }
      }
    }
    return rs16::encode_msop(p);
  }

  void serial(Input& in) {
    const std::size_t n = in.byte();
    if (n > 0) {
      const auto read = in.bytes(n);
      imu_.write(to_ns(t_s_), read);
      return;
    }
    std::array<float, 6> values{};
    const auto raw = in.bytes(sizeof values);
    std::memcpy(values.data(), raw.data(), raw.size());
    imu_frame(Eigen::Vector3d(values[0], values[1], values[2]), Eigen::Vector3d(values[3], values[4], values[5]));
  }

  std::uint32_t sender(std::uint8_t bits) const { return kSenderIps[bits % 3]; }

  void raw_datagram(Input& in) {
    const std::uint8_t flags = in.byte();
    const std::size_t length = (std::size_t{in.byte()} << 8) | in.byte();
    const auto payload = in.bytes(length);
    const std::uint16_t dst_port = kDstPorts[(flags >> 2) & 3];
    const std::uint16_t src_port = (flags & 3) == 3 ? 4000 : dst_port;
    tumble::pcap::make_udp_ethernet_frame(sender(flags & 3), kHostIp, src_port, dst_port, payload, frame_);
    lidar_.file().write(to_ns(t_s_), frame_);
  }

  void framed_datagram(Input& in) {
    const std::uint8_t flags = in.byte();
    const bool difop = (flags & 1) != 0;
    std::array<std::uint8_t, rs16::kPacketSize> packet{};
    const auto& magic = difop ? rs16::kDifopMagic : rs16::kMsopMagic;
    const auto body = in.bytes(rs16::kPacketSize - magic.size() - 2);
    std::copy(magic.begin(), magic.end(), packet.begin());
    std::copy(body.begin(), body.end(), packet.begin() + magic.size());
    const auto& tail = difop ? rs16::kDifopTail : rs16::kMsopTail;
    std::copy(tail.begin(), tail.end(), packet.begin() + rs16::kTailOffset);
    if (!difop) {
      rs16::encode_utc_time_ns(to_ns(t_s_), std::span(packet).subspan<rs16::kMsopTimeOffset, rs16::kUtcTimeSize>());
      for (int b = 0; b < rs16::kBlocks; ++b)
        std::copy(rs16::kBlockFlag.begin(), rs16::kBlockFlag.end(),
                  packet.begin() + rs16::kFirstBlockOffset + rs16::kBlockSize * b);
    }
    lidar_.write_from(sender((flags >> 1) & 3), to_ns(t_s_), difop ? rs16::PacketKind::Difop : rs16::PacketKind::Msop,
                      packet);
    t_s_ += kPacket_s;
  }

  static std::array<double, 16> laser_trig(double (*f)(double)) {
    std::array<double, 16> out{};
    for (int laser = 0; laser < 16; ++laser) out[laser] = f(rs16::kDesignVerticalAnglesDeg[laser] * M_PI / 180);
    return out;
  }

  const std::array<double, 16> cos_vertical_ = laser_trig([](double a) { return std::cos(a); });
  const std::array<double, 16> sin_vertical_ = laser_trig([](double a) { return std::sin(a); });
  rs16::RecordingWriter lidar_;
  mti::ImuRecordingWriter imu_;
  std::vector<std::uint8_t> frame_;
  double t_s_ = kStart_s;
  double next_packet_s_ = kStart_s;
  double next_difop_s_ = kStart_s;
  double azimuth_deg_ = 0.0;
  Eigen::Vector3d position_w_ = Eigen::Vector3d::Zero();
  double yaw_rad_ = 0.0;
  std::uint16_t packet_counter_ = 0;
  std::uint32_t sample_time_fine_ = 0;
};

bool verbose() {
  static const bool on = std::getenv("TUMBLE_FUZZ_DAEMON_VERBOSE") != nullptr;
  return on;
}

struct Published {
  std::vector<tumble::status_t> status;
  std::vector<tumble::odometry_t> odometry;
  std::vector<tumble::registration_t> poses;
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const tumble::status_t* m) { status.push_back(*m); }
  void on_odometry(const lcm::ReceiveBuffer*, const std::string&, const tumble::odometry_t* m) {
    odometry.push_back(*m);
  }
  void on_pose(const lcm::ReceiveBuffer*, const std::string&, const tumble::registration_t* m) {
    poses.push_back(*m);
  }
  // The state a subscriber saw at data time utime: the newest status stamped at or before it.
  bool tracking_at(std::int64_t utime) const {
    const tumble::status_t* newest = nullptr;
    for (const auto& s : status)
      if (s.utime <= utime && (newest == nullptr || s.utime >= newest->utime)) newest = &s;
    return newest != nullptr && newest->state == tumble::status_t::STATE_TRACKING;
  }
};

[[noreturn]] void fail(const char* what, std::int64_t utime) {
  std::fprintf(stderr, "fuzz_daemon: %s (utime %lld)\n", what, static_cast<long long>(utime));
  std::abort();
}

template <class Array>
bool all_finite(const Array& values) {
  for (const double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// What docs/lcm-interface.md tells a subscriber to check before using a pose,
// beyond the state: the odometry's flags, a registration's verdict.
bool trusted(const daemon::DaemonConfig&, const tumble::odometry_t& m) {
  return (m.flags & tumble::odometry_t::FLAG_INITIALISED) != 0 && (m.flags & tumble::odometry_t::FLAG_AWAITING_REST) == 0;
}
bool trusted(const daemon::DaemonConfig& config, const tumble::registration_t& m) {
  return m.registered && m.converged && !m.jumped && !m.direction_unobserved && !m.awaiting_rest &&
         m.expected_error_m <= config.daemon.health.max_expected_error_m;
}

// The farthest a trusted pose can be from the one before it on the same
// local map (`resets` unchanged: across a reset the trajectory is
// discontinuous by contract), dt_s apart: the fused speed limit
// (fuser.max_speed_m_s: beyond it the fuser declares the velocity runaway)
// over the time between them, plus one registration's correction of the
// IMU-propagated pose, which ICP bounds by its match distance
// (registration.max_match_distance_m). Republished odometry runs back in
// time: |dt| covers it.
double reachable_m(const daemon::DaemonConfig& config, double dt_s) {
  return config.fuser.max_speed_m_s * std::abs(dt_s) + config.registration.max_match_distance_m;
}

// Every pose published while tracking must be finite; every trusted one
// within reach of the trusted one before it. Returns how many were trusted.
template <class Pose>
std::size_t check_tracking_poses(const daemon::DaemonConfig& config, const Published& published,
                                 const std::vector<Pose>& poses, const char* channel) {
  const Pose* previous = nullptr;
  std::size_t count = 0;
  for (const Pose& pose : poses) {
    if (!published.tracking_at(pose.utime)) continue;
    if (!all_finite(pose.position_m) || !all_finite(pose.orientation) || !all_finite(pose.velocity_m_s))
      fail(channel, pose.utime);
    if (!trusted(config, pose)) continue;
    ++count;
    if (previous != nullptr && previous->resets == pose.resets) {
      const Eigen::Vector3d step = Eigen::Vector3d::Map(pose.position_m) - Eigen::Vector3d::Map(previous->position_m);
      if (step.norm() > reachable_m(config, (pose.utime - previous->utime) * 1e-6)) {
        std::fprintf(stderr, "fuzz_daemon: %s: a trusted tracking pose %.3f m from the one %.3f s before it\n",
                     channel, step.norm(), (pose.utime - previous->utime) * 1e-6);
        fail("a jump no motion can make", pose.utime);
      }
    }
    previous = &pose;
  }
  return count;
}

void print(const Published& published) {
  for (const auto& s : published.status)
    std::fprintf(stderr, "status %lld %s %s\n", static_cast<long long>(s.utime), s.state_name.c_str(),
                 s.state_reason.c_str());
  for (const auto& p : published.poses)
    std::fprintf(stderr,
                 "pose %lld tracking %d p %.3f %.3f %.3f registered %d converged %d jumped %d unobserved %d "
                 "awaiting_rest %d expected_error %.3f resets %d\n",
                 static_cast<long long>(p.utime), published.tracking_at(p.utime), p.position_m[0], p.position_m[1],
                 p.position_m[2], p.registered, p.converged, p.jumped, p.direction_unobserved, p.awaiting_rest,
                 p.expected_error_m, p.resets);
}

daemon::DaemonConfig fuzz_config() {
  daemon::DaemonConfig c;
  c.lcm.url = "memq://";
  c.daemon.status_period_s = 0.1;  // a status at every health evaluation: each pose's state is exact
  c.daemon.registration_threads = 1;
  // Small rings: less to allocate per input, and replay at max rate waits for room instead of dropping.
  c.daemon.imu_ring_capacity = 64;
  c.daemon.lidar_ring_capacity = 64;
  c.daemon.odometry_ring_capacity = 64;
  c.daemon.trajectory_buffer_capacity = 1024;
  // Less work per input, the same code: a shorter static start and coarser
  // voxels (fewer points to register, tracking from the first scans).
  c.fuser.init_static_s = 0.3;
  c.registration.voxel_size_m = 0.3;
  c.registration.icp_voxel_size_m = 0.6;
  c.map.voxel_size_m = 1.0;
  c.map.points_per_voxel = 20;
  return c;
}

struct Depth {
  std::size_t inputs = 0;
  std::size_t with_registered_scan = 0;
  std::size_t with_trusted_pose = 0;
  ~Depth() {
    std::fprintf(stderr, "fuzz_daemon: %zu inputs, %zu with a registered scan, %zu with a trusted pose published as tracking\n",
                 inputs, with_registered_scan, with_trusted_pose);
  }
};

Depth depth;
int lidar_fd = -1;
int imu_fd = -1;

std::string fd_path(int fd) { return "/proc/self/fd/" + std::to_string(fd); }

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(verbose() ? spdlog::level::info : spdlog::level::off);
  lidar_fd = memfd_create("fuzz_daemon_lidar.pcap", 0);
  imu_fd = memfd_create("fuzz_daemon_imu.pcap", 0);
  if (lidar_fd < 0 || imu_fd < 0) {
    std::perror("memfd_create");
    std::abort();
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Input in(data, size);
  Recordings(fd_path(lidar_fd), fd_path(imu_fd)).run(in);

  const daemon::DaemonConfig config = fuzz_config();
  lcm::LCM lcm(config.lcm.url);
  Published published;
  lcm.subscribe("TUMBLE_STATUS", &Published::on_status, &published);
  lcm.subscribe("TUMBLE_ODOM", &Published::on_odometry, &published);
  lcm.subscribe("TUMBLE_POSE", &Published::on_pose, &published);
  // Blocks SIGINT and SIGTERM for the run's threads (tumbled's main does it
  // before any thread starts); between inputs they stop the fuzzer as usual.
  daemon::ShutdownSignals signals;
  daemon::RunOptions options;
  options.replay = daemon::ReplayFiles{fd_path(lidar_fd), fd_path(imu_fd)};
  options.rate.max = true;
  if (daemon::run_daemon(config, options, lcm, signals, daemon::make_sensor_parts) != 0)
    fail("tumbled failed replaying the input", 0);
  while (lcm.handleTimeout(0) > 0) {
  }

  if (verbose()) print(published);
  std::size_t trusted_poses = check_tracking_poses(config, published, published.odometry, "TUMBLE_ODOM");
  trusted_poses += check_tracking_poses(config, published, published.poses, "TUMBLE_POSE");
  for (const auto& pose : published.poses)
    if (published.tracking_at(pose.utime) && !all_finite(pose.covariance)) fail("TUMBLE_POSE covariance", pose.utime);
  ++depth.inputs;
  for (const auto& pose : published.poses)
    if (pose.registered) {
      ++depth.with_registered_scan;
      break;
    }
  if (trusted_poses > 0) ++depth.with_trusted_pose;
  return 0;
}
