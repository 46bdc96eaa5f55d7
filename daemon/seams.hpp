// The interfaces the drivers and the core plug into. The daemon owns threads,
// rings and outputs; these say what runs on which thread:
//
//   io thread            LidarDatagramSource -> LidarDecoder -> PointBlock ring
//                        ImuByteSource -> ImuDecoder -> ImuSample ring
//                        (Recorder sees the raw bytes of both)
//   fuser thread         ImuSample ring + correction ring -> FuserStage
//                        -> trajectory buffer (seqlock) + odometry ring
//   registration thread  PointBlock ring -> RegistrationStage (scan assembly,
//                        de-skew, weights, ICP, map) + trajectory window
//                        -> correction ring, registration ring, scan reports
//
// Implementations never see a ring, a thread or a clock of the daemon: they
// get data and return data. Every time they return is seconds on the one
// host clock (see core/types.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "daemon/records.hpp"
#include "daemon/status_counters.hpp"

namespace tumble {
class scan_t;  // lcmtypes
class map_t;
}

namespace tumble::daemon {

struct LidarDatagram {
  double arrival_s = 0.0;    // host clock
  std::uint32_t src_ip = 0;  // host byte order
  std::uint16_t src_port = 0;
  std::uint16_t dst_port = 0;
  std::span<const std::uint8_t> payload;
};

struct ImuBytes {
  double arrival_s = 0.0;  // host clock, of the read that returned these bytes
  std::span<const std::uint8_t> bytes;
};

// Live UDP sockets or a pcap replay, driven by the io thread's io_context
// (which the source was constructed with). Callbacks run on the io thread.
class LidarDatagramSource {
 public:
  virtual ~LidarDatagramSource() = default;
  // Starts delivering; on_end is called once when a replay is exhausted (live sources never end).
  virtual void start(std::function<void(const LidarDatagram&)> on_datagram, std::function<void()> on_end) = 0;
  // Called on the io thread; no callback may follow.
  virtual void stop() = 0;
};

// A serial port (which the source configures itself when imu.configure is
// true) or a replay of recorded serial reads.
class ImuByteSource {
 public:
  virtual ~ImuByteSource() = default;
  virtual void start(std::function<void(const ImuBytes&)> on_bytes, std::function<void()> on_end) = 0;
  virtual void stop() = 0;
};

// rs16 MSOP/DIFOP decoding, on the io thread.
class LidarDecoder {
 public:
  virtual ~LidarDecoder() = default;
  // True when the datagram carried points, written to block (DIFOP, foreign
  // and bad datagrams return false and are counted by the decoder).
  virtual bool decode(const LidarDatagram& datagram, PointBlock& block) = 0;
  // Whether the last datagram decoded came from the lidar (not foreign, not
  // to another port), points or not: what a recording keeps.
  virtual bool last_from_the_lidar() const = 0;
  // Copies the decoder's cumulative statistics (lidar_* fields, lidar clock).
  virtual void report(PipelineCounters& counters) const = 0;
};

// Xbus/MTData2 decoding and the sensor-to-host time mapping, on the io thread.
class ImuDecoder {
 public:
  virtual ~ImuDecoder() = default;
  // Feeds bytes in arrival order; calls emit once per complete IMU sample, in time order.
  virtual void decode(const ImuBytes& bytes, const std::function<void(const ImuSample&)>& emit) = 0;
  // Copies the decoder's cumulative statistics (imu_* fields, IMU clock).
  virtual void report(PipelineCounters& counters) const = 0;
};

// Records a live run (record.dir), called on the io thread: the lidar's
// datagrams (the decoder accepted them) and every serial read.
class Recorder {
 public:
  virtual ~Recorder() = default;
  virtual void record_lidar(const LidarDatagram& datagram) = 0;
  virtual void record_imu(const ImuBytes& bytes) = 0;
  // Copies its cumulative counts (record_* fields).
  virtual void report(PipelineCounters& counters) const = 0;
  // Makes everything written so far complete on disk (called at shutdown).
  virtual void flush() = 0;
};

// The fuser thread's half of the odometry (core ImuFuser + trajectory).
class FuserStage {
 public:
  virtual ~FuserStage() = default;
  // One IMU sample, in time order. True with `out` filled when the sample
  // extends the trajectory; false while the fuser initialises (static average).
  virtual bool add_imu(const ImuSample& sample, TrajectoryRecord& out) = 0;
  // A registered scan (its pose at t_s), for the velocity filter and the
  // re-anchoring. When that rewrites trajectory samples already returned by
  // add_imu, republish is called with each of them again, in time order.
  virtual void add_correction(const RegistrationRecord& registration,
                              const std::function<void(const TrajectoryRecord&)>& republish) = 0;
};

// The registration thread's half: scan assembly, de-skew, weights, ICP, local map.
class RegistrationStage {
 public:
  struct TimeSpan {
    double start_s = 0.0;  // first point of the held scan
    double end_s = 0.0;    // last point
  };

  virtual ~RegistrationStage() = default;
  // Names of the timed stages (<= RegistrationRecord::kMaxStages), e.g. deskew, weights, icp, map.
  virtual std::vector<std::string> stage_names() const = 0;
  // One packet's points, in arrival order. True when they completed a scan,
  // which the stage then holds (keeping any points of the next scan) until
  // register_held_scan or discard_held_scan.
  virtual bool add_points(const PointBlock& block) = 0;
  virtual TimeSpan held_scan_span() const = 0;
  // Registers the held scan. `trajectory` is in time order and normally
  // brackets held_scan_span(); it may cover less (or nothing) when the IMU
  // stalled: the stage decides what it can do and reports it in `out`.
  // viewer_scan, when not null, receives the de-skewed filtered points in W.
  virtual void register_held_scan(std::span<const TrajectoryRecord> trajectory, RegistrationRecord& out,
                                  tumble::scan_t* viewer_scan) = 0;
  // The local map as it is after the newest registered scan, thinned, for viewers.
  virtual void fill_viewer_map(tumble::map_t& map) const = 0;
  // Drops the held scan (the daemon fell too far behind to de-skew it).
  virtual void discard_held_scan() = 0;
  // Copies the stage's cumulative statistics (lidar_missing_packets from scan assembly).
  virtual void report(PipelineCounters& counters) const = 0;
};

}  // namespace tumble::daemon
