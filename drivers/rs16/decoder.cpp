#include "drivers/rs16/decoder.hpp"

#include <spdlog/fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>

namespace tumble::rs16 {
namespace {

// Motor speeds the RS-16 can be set to lie well inside this.
constexpr double kMinRpm = 60.0;
constexpr double kMaxRpm = 3000.0;

void require(bool ok, const std::string& key, double value, const std::string& allowed) {
  if (!ok) throw std::invalid_argument("rs16." + key + " = " + std::to_string(value) + ": must be " + allowed);
}

std::string_view to_string(ReturnMode mode) {
  switch (mode) {
    case ReturnMode::Dual: return "dual";
    case ReturnMode::Strongest: return "strongest";
    case ReturnMode::Last: return "last";
  }
  return "unknown";
}

}  // namespace

void validate(const DecoderConfig& c) {
  require(std::isfinite(c.min_range_m) && c.min_range_m >= 0.0, "min_range_m", c.min_range_m, ">= 0");
  require(std::isfinite(c.max_range_m) && c.max_range_m > c.min_range_m, "max_range_m", c.max_range_m,
          "> min_range_m");
  require(c.default_rpm >= kMinRpm && c.default_rpm <= kMaxRpm, "default_rpm", c.default_rpm, "in 60..3000");
  if (c.vertical_angles_deg) {
    for (int i = 0; i < kLasers; ++i) {
      const double a = (*c.vertical_angles_deg)[i];
      require(std::isfinite(a) && std::abs(a) <= kMaxPlausibleVerticalAngleDeg,
              "vertical_angles_deg[" + std::to_string(i) + "]", a, "in -25..25 deg");
    }
  }
}

Decoder::Decoder(const DecoderConfig& config) : config_(config), clock_(config.clock_mapper) {
  validate(config);
  settings_.min_range_m = config.min_range_m;
  settings_.max_range_m = config.max_range_m;
  settings_.rpm = config.default_rpm;
  if (config.vertical_angles_deg)
    use_angles(*config.vertical_angles_deg, AngleSource::Config);
  else
    use_angles(kDesignVerticalAnglesDeg, AngleSource::Design);
}

void Decoder::use_angles(const std::array<double, kLasers>& vertical_deg, AngleSource source) {
  lasers_ = make_laser_table(vertical_deg, source);
  spdlog::info("rs16: using {} vertical angles (deg, lasers 0..15): {:.4f}{}", to_string(source),
               fmt::join(vertical_deg, ", "), source == AngleSource::Difop ? "" : " until the first DIFOP");
}

void Decoder::decode_difop(std::span<const std::uint8_t> bytes, DecoderStats& stats) {
  const PacketError e = rs16::decode_difop(bytes, difop_);
  if (e != PacketError::None) {
    count(e, stats.bad_difop);
    return;
  }
  ++stats.difop_packets;
  difop_seen_ = true;
  // Frozen once a DIFOP gave the vertical angles: one without them (a lidar
  // not calibrated yet) leaves the next to set them.
  if (!settings_frozen_ || config_.follow_difop_changes) {
    apply_difop(stats);
    settings_frozen_ = difop_.angles_calibrated;
    return;
  }
  const std::string changes = difop_changes();
  if (changes.empty()) return;
  ++stats.difop_ignored;
  if (!logged_ignored_)
    spdlog::warn("rs16: a DIFOP disagrees with the sensor configuration in use ({}): ignored, as every later one "
                 "(lidar.follow_difop_changes: false; counted in status_t.lidar_difop_ignored)",
                 changes);
  logged_ignored_ = true;
}

std::string Decoder::difop_changes() const {
  const DifopData& d = difop_.data;
  std::string changes;
  const auto add = [&changes](std::string_view what) { changes += (changes.empty() ? "" : ", ") + std::string(what); };
  if (difop_.angles_calibrated && d.vertical_angles_deg != lasers_.vertical_deg) add("vertical angles");
  if (difop_.resolution_m != settings_.resolution_m) add("range resolution");
  if (d.return_mode <= static_cast<std::uint8_t>(ReturnMode::Last) &&
      static_cast<ReturnMode>(d.return_mode) != settings_.return_mode)
    add("return mode");
  if (d.motor_rpm >= kMinRpm && d.motor_rpm <= kMaxRpm && d.motor_rpm != settings_.rpm) add("motor speed");
  return changes;
}

void Decoder::apply_difop(DecoderStats& stats) {
  const DifopData& d = difop_.data;
  if (!difop_.angles_calibrated) {
    ++stats.difop_uncalibrated;
    if (!logged_uncalibrated_)
      spdlog::warn("rs16: DIFOP carries no usable vertical angles; keeping the {} ones", to_string(lasers_.source));
    logged_uncalibrated_ = true;
  } else if (lasers_.source != AngleSource::Difop || lasers_.vertical_deg != d.vertical_angles_deg) {
    use_angles(d.vertical_angles_deg, AngleSource::Difop);
    logged_uncalibrated_ = false;
  }
  if (difop_.resolution_m != settings_.resolution_m) {
    spdlog::info("rs16: range resolution {} cm (top-board firmware {:02x} {:02x} {:02x})", difop_.resolution_m * 100,
                 d.top_firmware[0], d.top_firmware[1], d.top_firmware[2]);
    settings_.resolution_m = difop_.resolution_m;
  }
  if (d.return_mode <= static_cast<std::uint8_t>(ReturnMode::Last) &&
      static_cast<ReturnMode>(d.return_mode) != settings_.return_mode) {
    settings_.return_mode = static_cast<ReturnMode>(d.return_mode);
    spdlog::info("rs16: return mode {}", to_string(settings_.return_mode));
  }
  if (d.motor_rpm >= kMinRpm && d.motor_rpm <= kMaxRpm && d.motor_rpm != settings_.rpm) {
    settings_.rpm = d.motor_rpm;
    spdlog::info("rs16: motor speed {} rpm", d.motor_rpm);
  }
}

bool Decoder::decode_msop(std::span<const std::uint8_t> bytes, double arrival_s, DecodedPacket& out,
                          DecoderStats& stats) {
  if (config_.wait_for_difop && !difop_seen_) {
    ++stats.msop_before_difop;
    return false;
  }
  const PacketError e = parse_msop_header(bytes, header_);
  if (e != PacketError::None) {
    count(e, stats.bad_msop);
    return false;
  }
  const double lidar_t_s = static_cast<double>(header_.utc_time_ns) * 1e-9;
  const double host_t_s = config_.clock == ClockMode::Synced
                              ? lidar_t_s
                              : clock_.observe(lidar_t_s, arrival_s, packet_duration_s(settings_.return_mode));
  decode_msop_points(bytes, header_, host_t_s, lasers_, settings_, out, stats.dropped);
  ++stats.msop_packets;
  stats.msop_blocks_cut += static_cast<std::uint64_t>(kBlocks - header_.valid_blocks);
  stats.points += out.block_begin[out.block_count];
  return true;
}

}  // namespace tumble::rs16
