#include "tools/dump/mti_dump.hpp"

#include <cstdint>
#include <optional>
#include <vector>

#include "drivers/mti/imu_recording_reader.hpp"
#include "drivers/mti/sequence.hpp"

namespace tumble::dump {
namespace {

// What the summary needs beyond the driver's own counters.
struct MtiTally {
  std::uint64_t samples = 0;
  double first_host_s = 0;
  double last_host_s = 0;
  std::uint64_t sensor_timed = 0;
  std::int64_t first_ticks = 0;
  std::int64_t last_ticks = 0;
};

void write_row(const ImuSample& s, const mti::MtData2& m, std::optional<std::int64_t> ticks, std::FILE* out) {
  if (ticks) std::fprintf(out, "%.4f", static_cast<double>(*ticks) / mti::kSampleTimeFineHz);
  std::fprintf(out, ",%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,", s.t_s, s.accel_m_s2.x(), s.accel_m_s2.y(),
               s.accel_m_s2.z(), s.gyro_rad_s.x(), s.gyro_rad_s.y(), s.gyro_rad_s.z());
  if (m.status_word) std::fprintf(out, "0x%08x", static_cast<unsigned>(*m.status_word));
  std::fputc(',', out);
  static constexpr char kAxes[] = "XYZ";
  bool first = true;
  const auto axis = [&](char sensor, int i) {
    std::fprintf(out, "%s%c%c", first ? "" : " ", sensor, kAxes[i]);
    first = false;
  };
  for (int i = 0; i < 3; ++i)
    if (s.accel_saturated[i]) axis('a', i);
  for (int i = 0; i < 3; ++i)
    if (s.gyro_saturated[i]) axis('g', i);
  std::fputc('\n', out);
}

void tally_sample(const ImuSample& s, std::optional<std::int64_t> ticks, MtiTally& tally) {
  if (tally.samples == 0) tally.first_host_s = s.t_s;
  ++tally.samples;
  tally.last_host_s = s.t_s;
  if (!ticks) return;
  if (tally.sensor_timed == 0) tally.first_ticks = *ticks;
  ++tally.sensor_timed;
  tally.last_ticks = *ticks;
}

void write_summary(const std::string& path, const mti::ImuRecordingReader& reader, const MtiTally& tally,
                   std::FILE* out) {
  using ull = unsigned long long;
  const mti::MtiStats& s = reader.stats();
  const mti::FrameReaderStats& f = s.frames;
  std::fprintf(out, "file: %s\n", path.c_str());
  std::fprintf(out, "format: %s\n", reader.format() == mti::RecordingFormat::Pcap ? "pcap" : "raw bytes");
  std::fprintf(out, "reads: %llu\n", ull{reader.reads()});
  std::fprintf(out, "bytes: %llu (discarded %llu)\n", ull{f.bytes}, ull{f.bytes_discarded});
  std::fprintf(out, "frames: %llu\n", ull{f.frames});
  std::fprintf(out, "bad frames: %llu (checksum %llu, length %llu, bus id %llu, cut off %llu)\n", ull{f.bad_frames()},
               ull{f.bad_checksum}, ull{f.bad_length}, ull{f.bad_bus_id}, ull{f.cut_off});
  std::fprintf(out, "mtdata2 messages: %llu (truncated %llu, size mismatches %llu, unknown packets %llu)\n",
               ull{s.mtdata2.messages}, ull{s.mtdata2.truncated_messages}, ull{s.mtdata2.size_mismatches},
               ull{s.mtdata2.unknown_packets});
  std::fprintf(out, "imu samples: %llu\n", ull{s.imu_samples});
  std::fprintf(out, "non-imu messages: %llu\n", ull{s.non_imu_messages});
  std::fprintf(out, "other frames: %llu (device errors %llu)\n", ull{s.other_frames}, ull{s.device_errors});
  // From the sensor clock: arrival times carry the serial jitter.
  const double sensor_span_s = static_cast<double>(tally.last_ticks - tally.first_ticks) / mti::kSampleTimeFineHz;
  const double rate_hz = tally.sensor_timed >= 2 && sensor_span_s > 0
                             ? static_cast<double>(tally.sensor_timed - 1) / sensor_span_s
                             : 0.0;
  std::fprintf(out, "sample rate: %.2f Hz\n", rate_hz);
  std::fprintf(out, "sample time gaps: %llu\n", ull{s.sample_time_gaps});
  std::fprintf(out, "packet counter gaps: %llu (missing packets %llu)\n", ull{s.packet_counter_gaps},
               ull{s.missing_packets});
  std::fprintf(out, "duplicate frames (dropped): %llu\n", ull{s.duplicate_frames});
  std::fprintf(out, "out-of-order frames (dropped): %llu\n", ull{s.out_of_order_frames});
  std::fprintf(out, "samples back in time (dropped): %llu\n", ull{s.sample_time_backwards});
  std::fprintf(out, "sensor clock restarts: %llu\n", ull{s.sensor_clock_restarts});
  std::fprintf(out, "samples without sample time: %llu\n", ull{s.samples_without_sample_time});
  std::fprintf(out, "clipped samples: %llu\n", ull{s.clipped_samples});
  std::fprintf(out, "saturated: aX %llu aY %llu aZ %llu gX %llu gY %llu gZ %llu\n", ull{s.accel_saturated[0]},
               ull{s.accel_saturated[1]}, ull{s.accel_saturated[2]}, ull{s.gyro_saturated[0]},
               ull{s.gyro_saturated[1]}, ull{s.gyro_saturated[2]});
  std::fprintf(out, "host time span: %.6f s (%.6f to %.6f)\n", tally.last_host_s - tally.first_host_s,
               tally.first_host_s, tally.last_host_s);
  std::fprintf(out, "sensor time span: %.4f s\n", sensor_span_s);
  const std::string problem = reader.problem();
  std::fprintf(out, "problem: %s\n", problem.empty() ? "none" : problem.c_str());
}

}  // namespace

std::string dump_mti(const std::string& path, const MtiDumpOptions& options, std::FILE* out) {
  mti::ImuRecordingReader reader(path, options.stream);
  MtiTally tally;
  const bool summary = options.summary;
  reader.set_sample_observer(
      [&](const ImuSample& sample, const mti::MtData2& message, std::optional<std::int64_t> ticks) {
        if (summary) {
          tally_sample(sample, ticks, tally);
        } else {
          write_row(sample, message, ticks, out);
        }
      });
  if (!summary) std::fputs("t_sensor_s,t_host_s,ax,ay,az,gx,gy,gz,status_word,saturated_axes\n", out);
  std::vector<ImuSample> samples;  // rows are written by the observer; this only keeps the reader's contract
  while (reader.next(samples)) samples.clear();
  if (summary) write_summary(path, reader, tally, out);
  return reader.problem();
}

}  // namespace tumble::dump
