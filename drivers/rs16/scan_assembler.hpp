// Cuts the stream of decoded packets into scans (one revolution each) where
// the block azimuth passes the split azimuth, and notices packets that never
// came: from azimuth jumps between packets, and from time gaps of a
// revolution or more (or time running back as far), which end a scan rather
// than merge data from different revolutions into it.
//
// A scan that never passes the split azimuth (a stalled motor with the
// lasers firing, a corrupt azimuth) is cut at kMaxScanRevolutions, in time
// or in points, and flagged: one scan must not grow without bound. The
// revolutions are at the slower of the speed in use and kSlowestRpm: the
// speed in use is the default until the first DIFOP, and a lidar set to
// turn slower must not have each of its scans cut.
//
// What networks do to UDP is taken in stride: an exact duplicate of a recent
// packet is dropped; a packet older than the newest one (it arrived late) is
// put into the open scan at its place in firing-time order when it was fired
// after the scan began, else dropped, and never ends a scan. All are counted.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include "core/types.hpp"
#include "drivers/rs16/decoded_packet.hpp"
#include "drivers/rs16/decoder_stats.hpp"

namespace tumble::rs16 {

inline constexpr double kMaxScanRevolutions = 1.5;
inline constexpr double kSlowestRpm = 300.0;  // the RS-16's slowest motor setting (docs/sensors.md)

struct ScanAssemblerConfig {
  double split_azimuth_deg = 0.0;  // [0, 360)
  // A scan whose blocks cover less than this fraction of a turn is reported
  // short (ScanReport::short_coverage). [0, 1]; 0 reports none.
  double min_scan_coverage = 0.9;
};

// What the points of a scan do not show.
struct ScanReport {
  std::uint32_t returns_dropped = 0;  // returns of the scan's firings that gave no point
  bool ended_by_gap = false;          // cut short by a time gap, not by the split azimuth
  bool cut_at_bound = false;          // cut at kMaxScanRevolutions without passing the split azimuth
  double azimuth_coverage = 0.0;      // fraction of a turn its blocks cover (lost packets leave holes)
  bool short_coverage = false;        // below min_scan_coverage: not a whole revolution
};

// The handler may keep the points by swapping scan.points with a vector of its
// own (recycled, to avoid allocating); whatever is left is cleared and reused.
using ScanHandler = std::function<void(Scan& scan, const ScanReport& report)>;

class ScanAssembler {
 public:
  // Throws std::invalid_argument naming the key when split_azimuth_deg is
  // outside [0, 360) or min_scan_coverage outside [0, 1].
  ScanAssembler(const ScanAssemblerConfig& config, ScanHandler handler);

  void add(const DecodedPacket& packet, DecoderStats& stats);
  std::size_t pending_points() const { return scan_.points.size(); }

 private:
  // Enough to recognise a duplicate that arrives a few packets after the original.
  static constexpr std::size_t kRecentPackets = 16;
  struct PacketKey {
    double lidar_t_s = 0.0;
    std::uint16_t first_azimuth = 0;
    int block_count = 0;
  };

  enum class ScanEnd { Split, Gap, Bound };

  bool seen_recently(const DecodedPacket& packet);
  bool over_bound(const DecodedPacket& packet, int block) const;
  void add_late(const DecodedPacket& packet, DecoderStats& stats);
  void end_scan(ScanEnd end, DecoderStats& stats);

  double split_units_;  // 0.01 deg
  double min_coverage_;
  ScanHandler handler_;
  Scan scan_;
  ScanReport report_;
  int blocks_in_scan_ = 0;
  double scan_start_t_s_ = 0.0;   // first firing of the scan's first block
  double coverage_units_ = 0.0;   // 0.01 deg of turn the scan's blocks cover
  bool has_previous_ = false;
  double previous_t_s_ = 0.0;        // first firing of the newest packet
  double previous_block_t_s_ = 0.0;  // first firing of its last block
  std::uint16_t previous_azimuth_ = 0;
  std::array<PacketKey, kRecentPackets> recent_{};
  std::size_t recent_next_ = 0;
};

}  // namespace tumble::rs16
