#include "tools/calib/run_inputs.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>

#include "drivers/mti/imu_recording_reader.hpp"
#include "drivers/pcap/pcap_file.hpp"
#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "tools/calib/input_error.hpp"

namespace tumble::calib {
namespace {

template <std::size_t N>
Eigen::Matrix<double, N, 1> read_vector(const YAML::Node& node, const std::string& where) {
  if (!node || !node.IsSequence() || node.size() != N)
    throw InputError(where + ": expected a list of " + std::to_string(N) + " numbers");
  Eigen::Matrix<double, N, 1> v;
  for (std::size_t i = 0; i < N; ++i) {
    v(static_cast<Eigen::Index>(i)) = node[i].as<double>();
    if (!std::isfinite(v(static_cast<Eigen::Index>(i)))) throw InputError(where + ": not a finite number");
  }
  return v;
}

double read_positive(const YAML::Node& node, const std::string& where) {
  if (!node || !node.IsScalar()) throw InputError(where + ": missing");
  const double v = node.as<double>();
  if (!(v > 0) || !std::isfinite(v)) throw InputError(where + ": must be a positive number");
  return v;
}

}  // namespace

RunSetup read_run_setup(const std::filesystem::path& manifest_path) {
  const std::string file = manifest_path.string();
  if (!std::filesystem::exists(manifest_path)) throw InputError(file + ": missing");
  RunSetup setup;
  try {
    const YAML::Node root = YAML::LoadFile(file);
    const YAML::Node t_li = root["extrinsics"]["T_LI"];
    const Eigen::Vector3d translation = read_vector<3>(t_li["translation_m"], file + ": extrinsics.T_LI.translation_m");
    const Eigen::Vector4d xyzw = read_vector<4>(t_li["quaternion_xyzw"], file + ": extrinsics.T_LI.quaternion_xyzw");
    const Eigen::Quaterniond q(xyzw(3), xyzw(0), xyzw(1), xyzw(2));
    if (std::abs(q.norm() - 1.0) > 1e-6)
      throw InputError(file + ": extrinsics.T_LI.quaternion_xyzw: not a unit quaternion");
    setup.T_li = Eigen::Isometry3d::Identity();
    setup.T_li.linear() = q.normalized().toRotationMatrix();
    setup.T_li.translation() = translation;
    setup.imu_rate_hz = read_positive(root["imu"]["rate_hz"], file + ": imu.rate_hz");
    setup.imu_baud = static_cast<std::uint32_t>(read_positive(root["imu"]["baud"], file + ": imu.baud"));
  } catch (const YAML::Exception& e) {
    throw InputError(file + ": " + e.what());
  }
  return setup;
}

std::vector<ImuSample> read_imu_samples(const std::filesystem::path& path, const RunSetup& setup) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) throw InputError(file + ": missing");
  mti::MtiStreamOptions options;
  options.imu_rate_hz = setup.imu_rate_hz;
  options.baud = setup.imu_baud;
  std::vector<ImuSample> samples;
  try {
    mti::ImuRecordingReader reader(file, options);
    while (reader.next(samples)) {
    }
    if (const std::string problem = reader.problem(); !problem.empty()) throw InputError(problem);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
  if (samples.empty()) throw InputError(file + ": no IMU sample");
  return samples;
}

std::size_t for_each_scan(const std::filesystem::path& path, rs16::ClockMode clock,
                          const std::function<void(const Scan&)>& on_scan) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) throw InputError(file + ": missing");
  std::size_t scans = 0;
  rs16::DriverConfig config;
  config.decoder.clock = clock;
  rs16::Driver driver(config, [&](Scan& scan, const rs16::ScanReport&) {
    if (scan.points.empty()) return;
    ++scans;
    on_scan(scan);
  });
  try {
    rs16::PcapSource source(file, rs16::SourceConfig{});
    while (const auto datagram = source.next()) driver.on_datagram(*datagram);
    if (source.truncated()) throw InputError(source.error());
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(e.what());  // the driver's messages name the file
  }
  const rs16::DecoderStats& s = driver.stats();
  if (s.bad_msop.total() + s.bad_difop.total() > 0)
    throw InputError(file + ": " + std::to_string(s.bad_msop.total()) + " corrupt MSOP and " +
                     std::to_string(s.bad_difop.total()) + " corrupt DIFOP packets");
  if (scans == 0) throw InputError(file + ": no lidar scan");
  return scans;
}

}  // namespace tumble::calib
