// Stand-ins for the drivers and the core, to run the daemon's threads and
// queues end to end. A FakeRecording is a small merged "pcap pair": lidar
// packets and IMU reads with arrival times, delivered in arrival order on the
// io thread, as the real replay sources must. Scan s covers
// [s * scan_s, (s + 1) * scan_s); its packets carry 4 points each.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "daemon/pipeline.hpp"
#include "daemon/seams.hpp"
#include "test/daemon/good_registration.hpp"
#include "tumble/map_t.hpp"
#include "tumble/scan_t.hpp"

namespace tumble::daemon::fake {

constexpr double kScanS = 0.1;
constexpr int kPacketsPerScan = 10;
constexpr int kPointsPerPacket = 4;
constexpr double kImuPeriodS = 0.005;
constexpr int kImuSamplesBeforeInitialised = 4;

struct Event {
  double arrival_s;
  bool lidar;
  std::array<std::uint8_t, 16> bytes;  // lidar: first point time, scan, packet; IMU: sample time
};

class FakeRecording {
 public:
  // scans full revolutions of lidar data and IMU samples spanning them.
  explicit FakeRecording(boost::asio::io_context& io, int scans, bool ends = true) : io_(io), ends_(ends) {
    for (int s = 0; s < scans; ++s) {
      for (int p = 0; p < kPacketsPerScan; ++p) {
        const double first_point_s = s * kScanS + p * (kScanS / kPacketsPerScan);
        Event e{first_point_s + kScanS / kPacketsPerScan, true, {}};
        const std::uint32_t ids[2] = {static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(p)};
        std::memcpy(e.bytes.data(), &first_point_s, 8);
        std::memcpy(e.bytes.data() + 8, ids, 8);
        events_.push_back(e);
      }
    }
    for (int k = 0; k * kImuPeriodS <= scans * kScanS; ++k) {
      const double t = k * kImuPeriodS;
      Event e{t + 0.001, false, {}};
      std::memcpy(e.bytes.data(), &t, 8);
      events_.push_back(e);
    }
    std::stable_sort(events_.begin(), events_.end(),
                     [](const Event& a, const Event& b) { return a.arrival_s < b.arrival_s; });
  }

  class Source : public LidarDatagramSource, public ImuByteSource {
   public:
    explicit Source(FakeRecording& recording) : recording_(recording) {}
    void start(std::function<void(const LidarDatagram&)> on_datagram, std::function<void()> on_end) override {
      recording_.on_datagram_ = std::move(on_datagram);
      recording_.on_lidar_end_ = std::move(on_end);
      recording_.started();
    }
    void start(std::function<void(const ImuBytes&)> on_bytes, std::function<void()> on_end) override {
      recording_.on_bytes_ = std::move(on_bytes);
      recording_.on_imu_end_ = std::move(on_end);
      recording_.started();
    }
    void stop() override { recording_.stopped_ = true; }

   private:
    FakeRecording& recording_;
  };

  std::unique_ptr<LidarDatagramSource> lidar_source() { return std::make_unique<Source>(*this); }
  std::unique_ptr<ImuByteSource> imu_source() { return std::make_unique<Source>(*this); }

  // Called (on the io thread) with the arrival time of each event before it is delivered.
  std::function<void(double)> before_event;

 private:
  void started() {
    if (++starts_ == 2) deliver(0);
  }

  // One event per io_context handler, so stop() can interleave.
  void deliver(std::size_t i) {
    if (stopped_) return;
    if (i == events_.size()) {
      if (ends_) {
        on_lidar_end_();
        on_imu_end_();
      }
      return;
    }
    const Event& e = events_[i];
    if (before_event) before_event(e.arrival_s);
    if (e.lidar) {
      on_datagram_(LidarDatagram{e.arrival_s, 0x0A000001, 6699, 6699, e.bytes});
    } else {
      on_bytes_(ImuBytes{e.arrival_s, std::span<const std::uint8_t>(e.bytes.data(), 8)});
    }
    boost::asio::post(io_, [this, i] { deliver(i + 1); });
  }

  boost::asio::io_context& io_;
  bool ends_;
  std::vector<Event> events_;
  int starts_ = 0;
  bool stopped_ = false;
  std::function<void(const LidarDatagram&)> on_datagram_;
  std::function<void(const ImuBytes&)> on_bytes_;
  std::function<void()> on_lidar_end_;
  std::function<void()> on_imu_end_;
};

class FakeLidarDecoder : public LidarDecoder {
 public:
  // Packets from this one on in each scan carry no points (the lidar facing the sky).
  int pointless_from_packet = kPacketsPerScan;
  bool rejects_all = false;  // every datagram foreign, DIFOP or bad: none gives points

  bool last_from_the_lidar() const override { return !rejects_all; }
  bool decode(const LidarDatagram& d, PointBlock& block) override {
    if (rejects_all) return false;
    ++packets_;
    double first_point_s = 0.0;
    std::uint32_t ids[2];
    std::memcpy(&first_point_s, d.payload.data(), 8);
    std::memcpy(ids, d.payload.data() + 8, 8);
    block.t_s = first_point_s;
    block.block_count = 1;
    block.block_begin[0] = 0;
    block.block_begin[1] = static_cast<int>(ids[1]) < pointless_from_packet ? kPointsPerPacket : 0;
    for (int i = 0; i < block.block_begin[1]; ++i) {
      LidarPoint& p = block.points[static_cast<std::size_t>(i)];
      p.t_s = first_point_s + i * (kScanS / kPacketsPerScan / kPointsPerPacket);
      p.x_m = static_cast<float>(ids[0]);  // scan index
      p.y_m = static_cast<float>(ids[1]);  // packet index
    }
    return true;
  }
  void report(PipelineCounters& counters) const override { counters.lidar_packets.store(packets_); }

 private:
  std::int64_t packets_ = 0;
};

class FakeImuDecoder : public ImuDecoder {
 public:
  bool rejects_all = false;  // bytes that decode to no valid sample

  void decode(const ImuBytes& bytes, const std::function<void(const ImuSample&)>& emit) override {
    if (rejects_all) return;
    ++frames_;
    ImuSample sample;
    std::memcpy(&sample.t_s, bytes.bytes.data(), 8);
    sample.accel_m_s2 = Eigen::Vector3d(0.0, 0.0, 9.81);
    sample.gyro_saturated[2] = frames_ % 50 == 0;
    emit(sample);
  }
  void report(PipelineCounters& counters) const override { counters.imu_frames.store(frames_); }

 private:
  std::int64_t frames_ = 0;
};

// Moves at 1 m/s along x once initialised.
class FakeFuser : public FuserStage {
 public:
  std::chrono::milliseconds correction_delay{0};  // a slow fuser thread
  int samples_before_initialised = kImuSamplesBeforeInitialised;

  bool add_imu(const ImuSample& sample, TrajectoryRecord& out) override {
    if (++samples_ <= samples_before_initialised) return false;
    out = TrajectoryRecord{};
    out.t_s = sample.t_s;
    out.p_w_m = {sample.t_s, 0.0, 0.0};
    out.v_w_m_s = {1.0, 0.0, 0.0};
    out.lidar_corrected = corrections_ > 0;
    newest_s_ = sample.t_s;
    return true;
  }
  void add_correction(const RegistrationRecord&, const std::function<void(const TrajectoryRecord&)>&) override {
    newest_at_correction_s.push_back(newest_s_);
    if (correction_delay.count() > 0) std::this_thread::sleep_for(correction_delay);
    corrections_.fetch_add(1, std::memory_order_release);
  }
  int corrections() const { return corrections_.load(std::memory_order_acquire); }
  const std::atomic<int>& corrections_counter() const { return corrections_; }

  std::vector<double> newest_at_correction_s;  // the newest sample added when each correction came

 private:
  int samples_ = 0;
  double newest_s_ = -1.0;
  std::atomic<int> corrections_{0};
};

// Assembles scans by the scan index in x_m; reports what trajectory it was given.
class FakeRegistration : public RegistrationStage {
 public:
  std::function<void()> on_register;  // e.g. to throw
  // When set, each result's covariance[0] is how many corrections the fuser
  // had applied when this scan was registered.
  const std::atomic<int>* corrections_applied = nullptr;

  std::vector<std::string> stage_names() const override { return {"assemble", "icp"}; }

  bool add_points(const PointBlock& block) override {
    if (block.all_points().empty()) return !held_.empty();
    const auto scan = static_cast<std::int64_t>(block.points[0].x_m);
    if (!current_.empty() && scan != current_index_) {
      held_ = std::move(current_);
      held_index_ = current_index_;
      current_.clear();
    }
    current_index_ = scan;
    const auto points = block.all_points();
    current_.insert(current_.end(), points.begin(), points.end());
    return !held_.empty();
  }
  TimeSpan held_scan_span() const override { return {held_.front().t_s, held_.back().t_s}; }

  void register_held_scan(std::span<const TrajectoryRecord> trajectory, RegistrationRecord& out,
                          tumble::scan_t* viewer) override {
    if (on_register) on_register();
    out = good_registration();
    out.t_s = held_.front().t_s;
    out.scan_index = held_index_;
    out.position_m = {static_cast<double>(trajectory.size()), trajectory.empty() ? -1.0 : trajectory.front().t_s,
                      trajectory.empty() ? -1.0 : trajectory.back().t_s};
    out.iterations = static_cast<std::int32_t>(held_.size());
    if (corrections_applied != nullptr) out.covariance[0] = corrections_applied->load(std::memory_order_acquire);
    out.num_stages = 2;
    out.stage_ms = {0.5f, 2.0f};
    if (viewer != nullptr) {
      viewer->scan_index = held_index_;
      viewer->num_points = static_cast<std::int32_t>(held_.size());
      viewer->x_m.assign(held_.size(), 0.0f);
      viewer->y_m.assign(held_.size(), 0.0f);
      viewer->z_m.assign(held_.size(), 0.0f);
      viewer->sigma_s_m.assign(held_.size(), 0.0f);
      viewer->weight.assign(held_.size(), 1.0f);
      viewer->ring.assign(held_.size(), 0);
    }
    registered_index_ = held_index_;
    held_.clear();
  }
  // One map point per registered scan so far, at the origin.
  void fill_viewer_map(tumble::map_t& map) const override {
    map.scan_index = registered_index_;
    map.map_points = map.num_points = static_cast<std::int32_t>(registered_index_ + 1);
    map.x_m.assign(static_cast<std::size_t>(map.num_points), 0.0f);
    map.y_m = map.x_m;
    map.z_m = map.x_m;
  }
  void discard_held_scan() override { held_.clear(); }
  void report(PipelineCounters&) const override {}

 private:
  std::vector<LidarPoint> current_, held_;
  std::int64_t current_index_ = -1, held_index_ = -1, registered_index_ = -1;
};

struct FakeParts {
  PipelineParts parts;
  FakeFuser* fuser;
  FakeRegistration* registration;
  FakeLidarDecoder* lidar_decoder;
  FakeImuDecoder* imu_decoder;
};

inline FakeParts make_parts(FakeRecording& recording) {
  FakeParts f;
  f.parts.lidar_source = recording.lidar_source();
  f.parts.imu_source = recording.imu_source();
  auto lidar_decoder = std::make_unique<FakeLidarDecoder>();
  f.lidar_decoder = lidar_decoder.get();
  f.parts.lidar_decoder = std::move(lidar_decoder);
  auto imu_decoder = std::make_unique<FakeImuDecoder>();
  f.imu_decoder = imu_decoder.get();
  f.parts.imu_decoder = std::move(imu_decoder);
  auto fuser = std::make_unique<FakeFuser>();
  auto registration = std::make_unique<FakeRegistration>();
  f.fuser = fuser.get();
  f.registration = registration.get();
  f.parts.fuser = std::move(fuser);
  f.parts.registration = std::move(registration);
  return f;
}

}  // namespace tumble::daemon::fake
