// The stateful half of decoding: remembers what DIFOP said (vertical angles,
// range resolution, return mode, motor speed), maps the lidar clock to the
// host clock and turns MSOP packets into points. One per lidar, one thread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "drivers/rs16/decoded_packet.hpp"
#include "drivers/rs16/difop_decode.hpp"
#include "drivers/rs16/decoder_stats.hpp"
#include "drivers/rs16/lidar_clock.hpp"
#include "drivers/rs16/msop_decode.hpp"

namespace tumble::rs16 {

// synced: the header UTC is host time (PTP/GPS-synced lidar); free: the header
// clock is mapped to host time from arrival times (LidarClockMapper).
enum class ClockMode { Synced, Free };

struct DecoderConfig {
  double min_range_m = 0.4;
  double max_range_m = 200.0;
  ClockMode clock = ClockMode::Synced;
  ClockMapperConfig clock_mapper;
  // Replaces the design vertical angles until the first calibrated DIFOP.
  std::optional<std::array<double, kLasers>> vertical_angles_deg;
  // Skip MSOP packets until the first DIFOP, as RoboSense's own driver does.
  bool wait_for_difop = false;
  double default_rpm = 600.0;  // motor speed assumed until the first DIFOP
  // The first DIFOP sets the sensor configuration (vertical angles, range
  // resolution, return mode, motor speed); a later one that disagrees is
  // counted and ignored, unless this is set. Any host that reaches the DIFOP
  // port could otherwise re-calibrate the lidar mid-run.
  bool follow_difop_changes = false;
};

// Throws std::invalid_argument naming the key and its allowed range.
void validate(const DecoderConfig& config);

class Decoder {
 public:
  explicit Decoder(const DecoderConfig& config = {});

  // One MSOP payload that reached the host at arrival_s. True when out now
  // holds its points; otherwise the reason is counted in stats.
  bool decode_msop(std::span<const std::uint8_t> bytes, double arrival_s, DecodedPacket& out, DecoderStats& stats);
  // One DIFOP payload: the first sets the sensor settings (each logged once);
  // a later one that disagrees is counted (stats.difop_ignored), named in one
  // warning and ignored, unless config.follow_difop_changes.
  void decode_difop(std::span<const std::uint8_t> bytes, DecoderStats& stats);

  const LaserTable& lasers() const { return lasers_; }
  double resolution_m() const { return settings_.resolution_m; }
  ReturnMode return_mode() const { return settings_.return_mode; }
  double rpm() const { return settings_.rpm; }
  bool difop_seen() const { return difop_seen_; }
  const LidarClockMapper& clock() const { return clock_; }

 private:
  void use_angles(const std::array<double, kLasers>& vertical_deg, AngleSource source);
  void apply_difop(DecoderStats& stats);
  // What the decoded DIFOP would change in the settings in use, "" for nothing.
  std::string difop_changes() const;

  DecoderConfig config_;
  LaserTable lasers_;
  PointSettings settings_;
  LidarClockMapper clock_;
  bool difop_seen_ = false;
  bool logged_uncalibrated_ = false;
  bool settings_frozen_ = false;  // the first DIFOP was applied
  bool logged_ignored_ = false;
  MsopHeader header_;
  DifopInfo difop_;
};

}  // namespace tumble::rs16
