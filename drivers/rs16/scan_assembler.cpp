#include "drivers/rs16/scan_assembler.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tumble::rs16 {
namespace {

// Room for a dual-return revolution at the slowest motor speed's packet rate,
// so steady-state assembly does not allocate.
constexpr std::size_t kReservedPoints = 2 * 2 * 1802 * kLasers;

// Turn from one block azimuth to the next in 0.01 deg. The raw difference is
// only known modulo a turn; the elapsed time says which multiple it was, so a
// small backwards wobble stays small and a gap of most of a turn stays large.
double unwrapped_advance(std::uint16_t from, std::uint16_t to, double expected_advance) {
  double raw = static_cast<double>(to) - static_cast<double>(from);
  if (raw < 0.0) raw += kAzimuthUnitsPerTurn;
  return raw + kAzimuthUnitsPerTurn * std::round((expected_advance - raw) / kAzimuthUnitsPerTurn);
}

// prev < split <= prev + advance, with split taken modulo a turn.
bool passes(std::uint16_t from, double advance, double split) {
  if (advance <= 0.0) return false;
  while (split <= from) split += kAzimuthUnitsPerTurn;
  return split <= from + advance;
}

}  // namespace

ScanAssembler::ScanAssembler(const ScanAssemblerConfig& config, ScanHandler handler)
    : split_units_(config.split_azimuth_deg * 100.0), handler_(std::move(handler)) {
  if (!(config.split_azimuth_deg >= 0.0 && config.split_azimuth_deg < 360.0))
    throw std::invalid_argument("rs16.split_azimuth_deg = " + std::to_string(config.split_azimuth_deg) +
                                ": must be in [0, 360)");
  scan_.points.reserve(kReservedPoints);
}

void ScanAssembler::end_scan(bool by_gap, DecoderStats& stats) {
  if (blocks_in_scan_ > 0) {
    report_.ended_by_gap = by_gap;
    ++stats.scans;
    handler_(scan_, report_);
    ++scan_.index;
  }
  scan_.points.clear();
  scan_.missing_packets = 0;
  report_ = {};
  blocks_in_scan_ = 0;
}

void ScanAssembler::add(const DecodedPacket& packet, DecoderStats& stats) {
  if (packet.block_count == 0) return;
  const double revolution_s = 60.0 / packet.rpm;
  const double units_per_s = kAzimuthUnitsPerTurn / revolution_s;
  const double nominal_step = nominal_block_step(packet.rpm, packet.return_mode);
  std::uint32_t missing = 0;
  if (has_previous_) {
    const double dt_s = packet.t_s - previous_t_s_;
    if (!(dt_s > 0.0) || dt_s >= revolution_s) {
      ++stats.time_gaps;
      if (dt_s > 0.0) {
        // Capped so that a clock jump of years cannot overflow the counter.
        const double lost = std::min(std::round(dt_s / packet_duration_s(packet.return_mode)) - 1.0, 1e12);
        if (lost > 0.0) stats.missing_packets += static_cast<std::uint64_t>(lost);
      }
      end_scan(true, stats);
      has_previous_ = false;
    } else {
      // The first block should follow the previous packet's last one by one step;
      // every further packet length of turn is a packet that never came.
      const double advance = unwrapped_advance(previous_azimuth_, packet.block_azimuth[0],
                                               (packet.t_s - previous_block_t_s_) * units_per_s);
      const double lost = std::round((advance - nominal_step) / (nominal_step * kBlocks));
      if (lost > 0.0) missing = static_cast<std::uint32_t>(lost);
      stats.missing_packets += missing;
    }
  }
  for (int b = 0; b < packet.block_count; ++b) {
    const std::uint16_t azimuth = packet.block_azimuth[b];
    if (has_previous_) {
      const double elapsed_s = b == 0 ? packet.t_s - previous_block_t_s_ : block_period_s(packet.return_mode);
      const double advance = unwrapped_advance(previous_azimuth_, azimuth, elapsed_s * units_per_s);
      if (passes(previous_azimuth_, advance, split_units_)) end_scan(false, stats);
    }
    // Packets lost just before this one belong to the scan this packet starts in.
    if (b == 0) scan_.missing_packets += missing;
    const auto points = packet.block_points(b);
    scan_.points.insert(scan_.points.end(), points.begin(), points.end());
    report_.returns_dropped += packet.block_dropped[b];
    ++blocks_in_scan_;
    previous_azimuth_ = azimuth;
    has_previous_ = true;
  }
  previous_t_s_ = packet.t_s;
  previous_block_t_s_ = packet.t_s + block_period_s(packet.return_mode) * (packet.block_count - 1);
}

}  // namespace tumble::rs16
