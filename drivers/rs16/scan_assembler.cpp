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

// The turn block b of the packet covers: up to the next block, or one nominal
// step for the last. A step of more than two nominal ones is a restricted
// field of view or a corrupt azimuth, not turn the block saw.
double block_coverage(const DecodedPacket& packet, int b, double nominal_step) {
  if (b + 1 >= packet.block_count) return nominal_step;
  // nominal_step is also the turn expected in one block period.
  const double advance = unwrapped_advance(packet.block_azimuth[b], packet.block_azimuth[b + 1], nominal_step);
  return std::clamp(advance, 0.0, 2.0 * nominal_step);
}

}  // namespace

ScanAssembler::ScanAssembler(const ScanAssemblerConfig& config, ScanHandler handler)
    : split_units_(config.split_azimuth_deg * 100.0),
      min_coverage_(config.min_scan_coverage),
      handler_(std::move(handler)) {
  if (!(config.split_azimuth_deg >= 0.0 && config.split_azimuth_deg < 360.0))
    throw std::invalid_argument("rs16.split_azimuth_deg = " + std::to_string(config.split_azimuth_deg) +
                                ": must be in [0, 360)");
  if (!(config.min_scan_coverage >= 0.0 && config.min_scan_coverage <= 1.0))
    throw std::invalid_argument("lidar.min_scan_coverage = " + std::to_string(config.min_scan_coverage) +
                                ": must be in [0, 1]");
  scan_.points.reserve(kReservedPoints);
}

void ScanAssembler::end_scan(ScanEnd end, DecoderStats& stats) {
  if (blocks_in_scan_ > 0) {
    report_.ended_by_gap = end == ScanEnd::Gap;
    report_.cut_at_bound = end == ScanEnd::Bound;
    stats.scans_cut_at_bound += report_.cut_at_bound;
    report_.azimuth_coverage = coverage_units_ / kAzimuthUnitsPerTurn;
    // A little below one nominal step short of the threshold still passes:
    // where the split falls between two blocks is a matter of rounding.
    report_.short_coverage = report_.azimuth_coverage < min_coverage_ - 1e-3;
    stats.scans_short_coverage += report_.short_coverage;
    ++stats.scans;
    handler_(scan_, report_);
    ++scan_.index;
  }
  scan_.points.clear();
  scan_.missing_packets = 0;
  report_ = {};
  blocks_in_scan_ = 0;
  coverage_units_ = 0.0;
}

bool ScanAssembler::seen_recently(const DecodedPacket& packet) {
  const PacketKey key{packet.lidar_t_s, packet.block_azimuth[0], packet.block_count};
  for (const PacketKey& k : recent_) {
    if (k.block_count > 0 && k.lidar_t_s == key.lidar_t_s && k.first_azimuth == key.first_azimuth &&
        k.block_count == key.block_count)
      return true;
  }
  recent_[recent_next_] = key;
  recent_next_ = (recent_next_ + 1) % kRecentPackets;
  return false;
}

bool ScanAssembler::over_bound(const DecodedPacket& packet, int block) const {
  if (blocks_in_scan_ == 0) return false;
  const double block_t_s = packet.t_s + block_period_s(packet.return_mode) * block;
  const double rpm = std::min(packet.rpm, kSlowestRpm);
  const double revolution_s = 60.0 / rpm;
  const double blocks_per_turn = kAzimuthUnitsPerTurn / nominal_block_step(rpm, packet.return_mode);
  const double max_points = kMaxScanRevolutions * blocks_per_turn * kChannelsPerBlock;
  return block_t_s - scan_start_t_s_ >= kMaxScanRevolutions * revolution_s ||
         static_cast<double>(scan_.points.size() + packet.block_points(block).size()) > max_points;
}

void ScanAssembler::add_late(const DecodedPacket& packet, DecoderStats& stats) {
  // Fired before the open scan began: its scan has been handed on.
  if (blocks_in_scan_ == 0 || packet.t_s < scan_start_t_s_) {
    ++stats.late_packets_dropped;
    return;
  }
  ++stats.late_packets;
  const auto points = packet.all_points();
  if (!points.empty()) {
    const double t_s = points.front().t_s;
    const auto at = std::upper_bound(scan_.points.begin(), scan_.points.end(), t_s,
                                     [](double t, const LidarPoint& p) { return t < p.t_s; });
    scan_.points.insert(at, points.begin(), points.end());
  }
  const double nominal_step = nominal_block_step(packet.rpm, packet.return_mode);
  for (int b = 0; b < packet.block_count; ++b) {
    report_.returns_dropped += packet.block_dropped[b];
    coverage_units_ += block_coverage(packet, b, nominal_step);
  }
  blocks_in_scan_ += packet.block_count;
  // The packet after it counted it as lost.
  if (scan_.missing_packets > 0 && stats.missing_packets > 0) {
    --scan_.missing_packets;
    --stats.missing_packets;
  }
}

void ScanAssembler::add(const DecodedPacket& packet, DecoderStats& stats) {
  if (packet.block_count == 0) return;
  if (seen_recently(packet)) {
    ++stats.duplicate_packets;
    return;
  }
  const double revolution_s = 60.0 / packet.rpm;
  if (has_previous_ && packet.t_s < previous_t_s_ && previous_t_s_ - packet.t_s < revolution_s) {
    add_late(packet, stats);
    return;
  }
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
      end_scan(ScanEnd::Gap, stats);
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
      if (passes(previous_azimuth_, advance, split_units_)) end_scan(ScanEnd::Split, stats);
    }
    if (over_bound(packet, b)) end_scan(ScanEnd::Bound, stats);
    if (blocks_in_scan_ == 0) scan_start_t_s_ = packet.t_s + block_period_s(packet.return_mode) * b;
    // Packets lost just before this one belong to the scan this packet starts in.
    if (b == 0) scan_.missing_packets += missing;
    const auto points = packet.block_points(b);
    scan_.points.insert(scan_.points.end(), points.begin(), points.end());
    report_.returns_dropped += packet.block_dropped[b];
    coverage_units_ += block_coverage(packet, b, nominal_step);
    ++blocks_in_scan_;
    previous_azimuth_ = azimuth;
    has_previous_ = true;
  }
  previous_t_s_ = packet.t_s;
  previous_block_t_s_ = packet.t_s + block_period_s(packet.return_mode) * (packet.block_count - 1);
}

}  // namespace tumble::rs16
