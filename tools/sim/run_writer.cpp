#include "tools/sim/run_writer.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "drivers/pcap/pcap_file.hpp"
#include "drivers/pcap/udp_frame.hpp"
#include "tools/sim/pending_file.hpp"

namespace tumble::sim {
namespace {

namespace fs = std::filesystem;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

void write_lidar_pcap(const SimRun& run, const fs::path& path, RunSummary& summary) {
  PendingFile file(path);
  {
    pcap::Writer writer(file.temp().string(), pcap::kLinkEthernet);
    LidarStream stream = run.lidar_stream();
    LidarDatagram d;
    while (stream.next(d)) {
      const auto frame = pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, d.dst_port, d.dst_port, d.payload);
      writer.write(run.scenario().epoch_ns + d.arrival_ns, frame);
    }
    writer.close();
    summary.msop_packets = stream.msop_count();
    summary.difop_packets = stream.difop_count();
  }
  file.commit();
}

void write_imu_pcap(const SimRun& run, const fs::path& path, RunSummary& summary) {
  PendingFile file(path);
  {
    pcap::Writer writer(file.temp().string(), pcap::kLinkUser0);
    ImuStream stream = run.imu_stream();
    SerialRead read;
    while (stream.next(read)) {
      writer.write(run.scenario().epoch_ns + read.arrival_ns, read.bytes);
      ++summary.imu_reads;
    }
    writer.close();
    summary.imu_frames = stream.frame_count();
    summary.imu_clipped_frames = stream.clipped_count();
  }
  file.commit();
}

YAML::Node flow(const std::vector<double>& values) {
  YAML::Node n(values);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

YAML::Node flow(const Eigen::Vector3d& v) { return flow(std::vector<double>{v.x(), v.y(), v.z()}); }

}  // namespace

std::uint64_t write_ground_truth(const SimRun& run, const fs::path& path) {
  PendingFile file(path);
  std::uint64_t n = 0;
  {
    std::unique_ptr<std::FILE, FileCloser> out(std::fopen(file.temp().c_str(), "w"));
    if (!out) throw std::runtime_error(path.string() + ": cannot be written");
    std::fprintf(out.get(), "# lidar pose T_WL (scene frame W, z up); t = host clock, s since the Unix epoch\n");
    std::fprintf(out.get(), "# t x y z qx qy qz qw\n");
    const double rate_hz = run.scenario().ground_truth_rate_hz;
    const auto duration_ns = std::llround(run.duration_s() * 1e9);
    for (std::int64_t i = 0;; ++i) {
      const auto t_ns = std::llround(static_cast<double>(i) * 1e9 / rate_hz);
      if (t_ns > duration_ns) break;
      const Eigen::Isometry3d T = run.motion().at(static_cast<double>(t_ns) * 1e-9).T_wb;
      const Eigen::Quaterniond q(T.linear());
      const Eigen::Vector3d p = T.translation();
      const std::int64_t host_ns = run.scenario().epoch_ns + t_ns;
      std::fprintf(out.get(), "%lld.%09lld %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                   static_cast<long long>(host_ns / 1'000'000'000), static_cast<long long>(host_ns % 1'000'000'000),
                   p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
      ++n;
    }
    if (std::ferror(out.get())) throw std::runtime_error(path.string() + ": write failed");
  }
  file.commit();
  return n;
}

void write_manifest(const SimRun& run, const RunSummary& summary, const fs::path& path) {
  const Scenario& s = run.scenario();
  const YAML::Node settings = scenario_to_yaml(s);
  YAML::Node m;
  m["format"] = "tumble-sim run 1";
  m["scenario"] = s.source_name;
  m["scene"] = s.scene_ref;
  m["scene_path"] = s.scene_path.string();
  m["motion"] = s.motion_ref;
  m["seed"] = s.seed;
  if (s.motion_seed) m["motion_seed"] = *s.motion_seed;
  m["duration_s"] = run.duration_s();
  m["epoch_utc"] = format_utc(s.epoch_ns);
  m["epoch_ns"] = s.epoch_ns;

  YAML::Node files;
  files["lidar_pcap"] = kLidarPcapName;
  files["imu_pcap"] = kImuPcapName;
  files["ground_truth"] = kGroundTruthName;
  m["files"] = files;
  YAML::Node gt;
  gt["rate_hz"] = s.ground_truth_rate_hz;
  gt["poses"] = summary.ground_truth_poses;
  gt["pose"] = "T_WL: lidar frame in the scene frame W (z up, gravity -z)";
  gt["time"] = "host clock, seconds since the Unix epoch (= epoch_ns + run time)";
  m["ground_truth"] = gt;

  const Eigen::Quaterniond q_li(s.T_LI.linear());
  YAML::Node extrinsics = settings["extrinsics"];
  extrinsics["T_LI"]["quaternion_xyzw"] = flow(std::vector<double>{q_li.x(), q_li.y(), q_li.z(), q_li.w()});
  extrinsics["T_LI"]["meaning"] = "IMU frame in the lidar frame: p_L = T_LI p_I";
  m["extrinsics"] = extrinsics;

  YAML::Node lidar = settings["lidar"];
  lidar["model"] = "RS-LiDAR-16, single (strongest) return";
  lidar["src_ip"] = "192.168.1.200";
  lidar["dst_ip"] = "192.168.1.102";
  lidar["clock"] = "synced: header UTC = host clock";
  lidar["unit_seed"] = s.lidar_unit_seed.value_or(s.seed);
  lidar["vertical_angles_deg"] =
      flow(std::vector<double>(run.lidar_unit().vertical_angles_deg.begin(), run.lidar_unit().vertical_angles_deg.end()));
  if (s.lidar.range_offset_error) {
    lidar["range_offsets_m"] =
        flow(std::vector<double>(run.lidar_unit().range_offsets_m.begin(), run.lidar_unit().range_offsets_m.end()));
  }
  lidar["first_packet_s"] = static_cast<double>(run.lidar_timing().first_packet_ns) * 1e-9;
  lidar["first_difop_s"] = static_cast<double>(run.lidar_timing().first_difop_ns) * 1e-9;
  lidar["azimuth_at_zero_deg"] = run.lidar_timing().azimuth_at_zero_deg;
  lidar["msop_packets"] = summary.msop_packets;
  lidar["difop_packets"] = summary.difop_packets;
  m["lidar"] = lidar;

  YAML::Node imu = settings["imu"];
  imu["model"] = "MTi-30 (MTData2: PacketCounter, SampleTimeFine, Acceleration, RateOfTurn, StatusWord)";
  YAML::Node clock;
  clock["drift_ppm"] = run.imu_clock().drift_ppm;
  clock["first_sample_s"] = run.imu_clock().first_sample_s;
  clock["first_sample_time_fine"] = run.imu_clock().first_sample_time_fine;
  clock["first_packet_counter"] = run.imu_clock().first_packet_counter;
  clock["meaning"] = "sample k at run time first_sample_s + k / rate_hz / (1 + drift_ppm 1e-6)";
  imu["clock"] = clock;
  const ImuStream probe = run.imu_stream();
  imu["initial_gyro_bias_rad_s"] = flow(probe.model().initial_gyro_bias_rad_s());
  imu["initial_accel_bias_m_s2"] = flow(probe.model().initial_accel_bias_m_s2());
  // The unit errors drawn for this run, where a source is on (an estimator's answer key).
  const ImuUnitErrors& errors = probe.model().unit_errors();
  const auto matrix = [](const Eigen::Matrix3d& a) {
    return flow(std::vector<double>{a(0, 0), a(0, 1), a(0, 2), a(1, 0), a(1, 1), a(1, 2), a(2, 0), a(2, 1), a(2, 2)});
  };
  if (s.imu.scale_factor_error || s.imu.misalignment) {
    imu["gyro_sensing_matrix"] = matrix(errors.gyro_sensing);
    imu["accel_sensing_matrix"] = matrix(errors.accel_sensing);
  }
  if (s.imu.g_sensitivity) imu["gyro_g_sensitivity_rad_s_per_m_s2"] = matrix(errors.gyro_g_sensitivity_rad_s_per_m_s2);
  if (s.imu.temperature_drift) {
    imu["gyro_warm_up_drift_rad_s"] = flow(errors.gyro_warm_up_drift_rad_s);
    imu["accel_warm_up_drift_m_s2"] = flow(errors.accel_warm_up_drift_m_s2);
  }
  imu["frames"] = summary.imu_frames;
  imu["reads"] = summary.imu_reads;
  imu["clipped_frames"] = summary.imu_clipped_frames;
  m["imu"] = imu;
  if (s.people.any()) {
    YAML::Node people = settings["people"];
    // The walkers' paths as walked (drawn from the seed unless listed).
    for (const WalkerPath& w : run.people().walkers()) {
      YAML::Node path;
      path["from_m"] = flow(std::vector<double>{w.from_m.x(), w.from_m.y()});
      path["to_m"] = flow(std::vector<double>{w.to_m.x(), w.to_m.y()});
      path["speed_m_s"] = w.speed_m_s;
      path["start_m"] = w.start_m;
      people["walker_paths"].push_back(path);
    }
    m["people"] = people;
  }
  m["motion_description"] = s.motion;

  PendingFile file(path);
  {
    std::ofstream out(file.temp());
    YAML::Emitter e;
    e << m;
    out << e.c_str() << "\n";
    if (!out) throw std::runtime_error(path.string() + ": write failed");
  }
  file.commit();
}

RunSummary write_run(const SimRun& run, const fs::path& out_dir) {
  fs::create_directories(out_dir);
  RunSummary summary;
  summary.duration_s = run.duration_s();
  write_lidar_pcap(run, out_dir / kLidarPcapName, summary);
  write_imu_pcap(run, out_dir / kImuPcapName, summary);
  summary.ground_truth_poses = write_ground_truth(run, out_dir / kGroundTruthName);
  write_manifest(run, summary, out_dir / kManifestName);
  return summary;
}

}  // namespace tumble::sim
