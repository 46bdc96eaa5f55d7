#include "drivers/rs16/decoder_stats.hpp"

namespace tumble::rs16 {
namespace {

void add(BadPackets& a, const BadPackets& b) {
  a.wrong_size += b.wrong_size;
  a.wrong_magic += b.wrong_magic;
  a.wrong_tail += b.wrong_tail;
  a.bad_timestamp += b.bad_timestamp;
  a.no_valid_blocks += b.no_valid_blocks;
}

}  // namespace

DecoderStats& DecoderStats::operator+=(const DecoderStats& o) {
  msop_packets += o.msop_packets;
  difop_packets += o.difop_packets;
  add(bad_msop, o.bad_msop);
  add(bad_difop, o.bad_difop);
  msop_blocks_cut += o.msop_blocks_cut;
  difop_uncalibrated += o.difop_uncalibrated;
  msop_before_difop += o.msop_before_difop;
  dropped.zero_range += o.dropped.zero_range;
  dropped.too_near += o.dropped.too_near;
  dropped.too_far += o.dropped.too_far;
  points += o.points;
  missing_packets += o.missing_packets;
  time_gaps += o.time_gaps;
  scans += o.scans;
  duplicate_packets += o.duplicate_packets;
  late_packets += o.late_packets;
  late_packets_dropped += o.late_packets_dropped;
  scans_short_coverage += o.scans_short_coverage;
  scans_cut_at_bound += o.scans_cut_at_bound;
  difop_ignored += o.difop_ignored;
  return *this;
}

}  // namespace tumble::rs16
