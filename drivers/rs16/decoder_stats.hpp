// Counters of everything the RS-16 driver accepted, dropped or noticed
// missing. Plain data: a thread owns its copy; add copies to report them.
#pragma once

#include <cstdint>

namespace tumble::rs16 {

// Why a packet was rejected as a whole.
struct BadPackets {
  std::uint64_t wrong_size = 0;
  std::uint64_t wrong_magic = 0;
  std::uint64_t wrong_tail = 0;
  std::uint64_t bad_timestamp = 0;    // MSOP header time is not a calendar date
  std::uint64_t no_valid_blocks = 0;  // MSOP whose first block already has a wrong flag or azimuth

  std::uint64_t total() const { return wrong_size + wrong_magic + wrong_tail + bad_timestamp + no_valid_blocks; }
};

// Why single returns were not turned into points.
struct DroppedPoints {
  std::uint64_t zero_range = 0;  // raw distance 0: no return
  std::uint64_t too_near = 0;    // below min_range_m
  std::uint64_t too_far = 0;     // beyond max_range_m

  std::uint64_t total() const { return zero_range + too_near + too_far; }
};

struct DecoderStats {
  std::uint64_t msop_packets = 0;   // decoded into points
  std::uint64_t difop_packets = 0;  // accepted
  BadPackets bad_msop;
  BadPackets bad_difop;
  std::uint64_t msop_blocks_cut = 0;     // blocks after a wrong flag or azimuth, ignored
  std::uint64_t difop_uncalibrated = 0;  // DIFOP whose vertical angles were unusable (kept the previous ones)
  std::uint64_t difop_ignored = 0;       // DIFOP after the first that disagreed with the settings in use
  std::uint64_t msop_before_difop = 0;   // skipped while waiting for the first DIFOP (wait_for_difop)
  DroppedPoints dropped;
  std::uint64_t points = 0;           // points produced
  std::uint64_t missing_packets = 0;  // inferred from azimuth jumps between packets
  std::uint64_t time_gaps = 0;        // scans ended by a gap of a revolution or more, or by time going back
  std::uint64_t scans = 0;            // scans emitted
  std::uint64_t duplicate_packets = 0;     // exact repeats of a recent packet: dropped
  std::uint64_t late_packets = 0;          // older than the newest: put into their (still open) scan
  std::uint64_t late_packets_dropped = 0;  // older than the newest, fired before the open scan began: dropped
  std::uint64_t scans_short_coverage = 0;  // scans emitted covering less than min_scan_coverage of a turn
  std::uint64_t scans_cut_at_bound = 0;    // scans cut at kMaxScanRevolutions without passing the split azimuth

  DecoderStats& operator+=(const DecoderStats& o);
};

}  // namespace tumble::rs16
