// Cuts the stream of decoded packets into scans (one revolution each) where
// the block azimuth passes the split azimuth, and notices packets that never
// came: from azimuth jumps between packets, and from time gaps of a
// revolution or more (or time running back), which end a scan rather than
// merge data from different revolutions into it.
#pragma once

#include <cstdint>
#include <functional>

#include "core/types.hpp"
#include "drivers/rs16/decoded_packet.hpp"
#include "drivers/rs16/decoder_stats.hpp"

namespace tumble::rs16 {

struct ScanAssemblerConfig {
  double split_azimuth_deg = 0.0;  // [0, 360)
};

// What the points of a scan do not show.
struct ScanReport {
  std::uint32_t returns_dropped = 0;  // returns of the scan's firings that gave no point
  bool ended_by_gap = false;          // cut short by a time gap, not by the split azimuth
};

// The handler may keep the points by swapping scan.points with a vector of its
// own (recycled, to avoid allocating); whatever is left is cleared and reused.
using ScanHandler = std::function<void(Scan& scan, const ScanReport& report)>;

class ScanAssembler {
 public:
  // Throws std::invalid_argument when split_azimuth_deg is outside [0, 360).
  ScanAssembler(const ScanAssemblerConfig& config, ScanHandler handler);

  void add(const DecodedPacket& packet, DecoderStats& stats);
  std::size_t pending_points() const { return scan_.points.size(); }

 private:
  void end_scan(bool by_gap, DecoderStats& stats);

  double split_units_;  // 0.01 deg
  ScanHandler handler_;
  Scan scan_;
  ScanReport report_;
  int blocks_in_scan_ = 0;
  bool has_previous_ = false;
  double previous_t_s_ = 0.0;        // first firing of the previous packet
  double previous_block_t_s_ = 0.0;  // first firing of its last block
  std::uint16_t previous_azimuth_ = 0;
};

}  // namespace tumble::rs16
