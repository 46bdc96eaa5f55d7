#include "tools/dump/rs16_dump.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "drivers/rs16/pcap_source.hpp"

namespace tumble::dump {
namespace {

// What the summary needs beyond the driver's own counters.
struct Rs16Tally {
  bool any_datagram = false;
  double first_arrival_s = 0;
  double last_arrival_s = 0;
  std::vector<std::size_t> points_per_scan;
  double first_point_s = 0;
  std::vector<double> scan_end_s;  // last point of each scan
  std::uint64_t points_in_scans = 0;
  std::uint64_t scans_with_missing_packets = 0;
};

void write_rows(const Scan& scan, std::FILE* out) {
  for (const LidarPoint& p : scan.points)
    std::fprintf(out, "%llu,%u,%.6f,%.4f,%.4f,%.4f,%g,%.3f\n", static_cast<unsigned long long>(scan.index),
                 static_cast<unsigned>(p.laser), p.t_s, static_cast<double>(p.x_m), static_cast<double>(p.y_m),
                 static_cast<double>(p.z_m), static_cast<double>(p.intensity), static_cast<double>(p.azimuth_deg));
}

void tally_scan(const Scan& scan, Rs16Tally& tally) {
  tally.points_per_scan.push_back(scan.points.size());
  if (scan.missing_packets > 0) ++tally.scans_with_missing_packets;
  tally.points_in_scans += scan.points.size();
  if (scan.points.empty()) return;
  if (tally.scan_end_s.empty()) tally.first_point_s = scan.points.front().t_s;
  tally.scan_end_s.push_back(scan.points.back().t_s);
}

double rate_hz(double count, double span_s) { return span_s > 0 ? count / span_s : 0.0; }

void write_bad(std::FILE* out, const char* kind, const rs16::BadPackets& b) {
  std::fprintf(out,
               "bad %s packets: %llu (wrong size %llu, wrong magic %llu, wrong tail %llu, bad timestamp %llu, "
               "no valid blocks %llu)\n",
               kind, static_cast<unsigned long long>(b.total()), static_cast<unsigned long long>(b.wrong_size),
               static_cast<unsigned long long>(b.wrong_magic), static_cast<unsigned long long>(b.wrong_tail),
               static_cast<unsigned long long>(b.bad_timestamp), static_cast<unsigned long long>(b.no_valid_blocks));
}

void write_summary(const std::string& path, const rs16::PcapSource& source, const rs16::Driver& driver,
                   Rs16Tally& tally, std::FILE* out) {
  using ull = unsigned long long;
  const rs16::PcapSourceStats& src = source.stats();
  const rs16::DecoderStats& s = driver.stats();
  std::fprintf(out, "file: %s\n", path.c_str());
  std::fprintf(out, "pcap records: %llu (not UDP %llu, other port %llu, wrong source %llu)\n", ull{src.records},
               ull{src.not_udp}, ull{src.other_port}, ull{src.wrong_source});
  std::fprintf(out, "msop packets: %llu (decoded %llu)\n", ull{src.msop}, ull{s.msop_packets});
  std::fprintf(out, "difop packets: %llu (accepted %llu, uncalibrated %llu)\n", ull{src.difop}, ull{s.difop_packets},
               ull{s.difop_uncalibrated});
  write_bad(out, "msop", s.bad_msop);
  write_bad(out, "difop", s.bad_difop);
  std::fprintf(out, "msop blocks cut: %llu\n", ull{s.msop_blocks_cut});
  std::fprintf(out, "msop before first difop: %llu\n", ull{s.msop_before_difop});
  std::fprintf(out, "scans: %llu\n", ull{s.scans});
  std::vector<std::size_t>& sizes = tally.points_per_scan;
  if (!sizes.empty()) {
    std::sort(sizes.begin(), sizes.end());
    std::fprintf(out, "points per scan: min %zu median %zu max %zu\n", sizes.front(), sizes[sizes.size() / 2],
                 sizes.back());
  }
  std::fprintf(out, "points: %llu (in scans %llu, in the unfinished last scan %zu)\n", ull{s.points},
               ull{tally.points_in_scans}, driver.assembler().pending_points());
  std::fprintf(out, "dropped points: %llu (zero range %llu, too near %llu, too far %llu)\n", ull{s.dropped.total()},
               ull{s.dropped.zero_range}, ull{s.dropped.too_near}, ull{s.dropped.too_far});
  std::fprintf(out, "missing packets: %llu (in %llu scans)\n", ull{s.missing_packets},
               ull{tally.scans_with_missing_packets});
  std::fprintf(out, "time gaps: %llu\n", ull{s.time_gaps});
  std::fprintf(out, "duplicate packets (dropped): %llu\n", ull{s.duplicate_packets});
  std::fprintf(out, "late packets: %llu put into their scan, %llu dropped (scan handed on)\n", ull{s.late_packets},
               ull{s.late_packets_dropped});
  std::fprintf(out, "scans with short coverage: %llu\n", ull{s.scans_short_coverage});
  const double arrival_span_s = tally.any_datagram ? tally.last_arrival_s - tally.first_arrival_s : 0.0;
  std::fprintf(out, "msop packet rate: %.1f Hz\n", rate_hz(static_cast<double>(src.msop), arrival_span_s));
  // Between scan ends (the split azimuth), so a partial first scan does not skew it.
  const auto& ends = tally.scan_end_s;
  const double scan_span_s = ends.size() >= 2 ? ends.back() - ends.front() : 0.0;
  std::fprintf(out, "scan rate: %.2f Hz\n", rate_hz(static_cast<double>(ends.size()) - 1.0, scan_span_s));
  std::fprintf(out, "arrival time span: %.6f s (%.6f to %.6f)\n", arrival_span_s, tally.first_arrival_s,
               tally.last_arrival_s);
  if (!ends.empty())
    std::fprintf(out, "scan time span: %.6f s (%.6f to %.6f)\n", ends.back() - tally.first_point_s,
                 tally.first_point_s, ends.back());
}

}  // namespace

std::string dump_rs16(const std::string& path, const Rs16DumpOptions& options, std::FILE* out) {
  rs16::validate(options.source);
  rs16::validate(options.driver.decoder);
  Rs16Tally tally;
  const bool summary = options.summary;
  rs16::Driver driver(options.driver, [&](Scan& scan, const rs16::ScanReport&) {
    if (summary) {
      tally_scan(scan, tally);
    } else {
      write_rows(scan, out);
    }
  });
  rs16::PcapSource source(path, options.source);
  if (!summary) std::fputs("scan,laser,t_s,x,y,z,intensity,azimuth_deg\n", out);
  while (const auto datagram = source.next()) {
    if (!tally.any_datagram) tally.first_arrival_s = datagram->arrival_s;
    tally.any_datagram = true;
    tally.last_arrival_s = datagram->arrival_s;
    driver.on_datagram(*datagram);
  }
  if (summary) write_summary(path, source, driver, tally, out);
  return source.error();
}

}  // namespace tumble::dump
