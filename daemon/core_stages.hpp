// The core's odometry split across the daemon's two compute threads
// (seams.hpp): ImuFuser on the fuser thread, scan assembly and
// ScanRegistration on the registration thread. The registration thread sees
// the trajectory only as the TrajectoryRecords the fuser published; it
// rebuilds a core Trajectory from the window around each scan.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/imu_fuser.hpp"
#include "core/scan_registration.hpp"
#include "core/trajectory.hpp"
#include "daemon/rate_limited_log.hpp"
#include "daemon/seams.hpp"
#include "daemon/worker_pool.hpp"
#include "drivers/rs16/decoder_stats.hpp"
#include "drivers/rs16/scan_assembler.hpp"

namespace tumble::daemon {

TrajectoryRecord to_record(const TrajectorySample& sample);
TrajectorySample to_sample(const TrajectoryRecord& record);

class CoreFuserStage : public FuserStage {
 public:
  explicit CoreFuserStage(const OdometryParams& params);

  bool add_imu(const ImuSample& sample, TrajectoryRecord& out) override;
  void add_correction(const RegistrationRecord& registration,
                      const std::function<void(const TrajectoryRecord&)>& republish) override;

 private:
  TrajectoryRecord record_of(const TrajectorySample& sample) const;

  OdometryParams params_;
  ImuFuser fuser_;
  double newest_published_s_ = -1e300;
};

class CoreRegistrationStage : public RegistrationStage {
 public:
  // threads: the registration thread plus threads − 1 helpers (WorkerPool),
  // each starting with on_helper_start(helper number).
  CoreRegistrationStage(const OdometryParams& params, const rs16::ScanAssemblerConfig& scans, std::size_t threads = 1,
                        std::function<void(std::size_t)> on_helper_start = {});

  std::vector<std::string> stage_names() const override;
  bool add_points(const PointBlock& block) override;
  TimeSpan held_scan_span() const override;
  void register_held_scan(std::span<const TrajectoryRecord> trajectory, RegistrationRecord& out,
                          tumble::scan_t* viewer_scan) override;
  void discard_held_scan() override;
  void report(PipelineCounters& counters) const override;

 private:
  void fill_record(const ScanResult& result, std::span<const TrajectoryRecord> trajectory, RegistrationRecord& out);
  void fill_viewer_scan(const ScanResult& result, tumble::scan_t& scan) const;
  void warn_of_packet_faults(const rs16::DecoderStats& before, double now_s);

  OdometryParams params_;
  double min_scan_coverage_;
  rs16::ScanAssembler assembler_;
  rs16::DecoderStats assembly_stats_;
  RateLimitedLog fault_log_{1, 10.0};  // duplicated, late and short scans, once per period each
  WorkerPool pool_;  // before registration_, which keeps a reference
  ScanRegistration registration_;
  Trajectory trajectory_;
  Scan held_;
  bool holding_ = false;
  ScanResult result_;
  std::vector<float> sigma_scratch_;
};

}  // namespace tumble::daemon
