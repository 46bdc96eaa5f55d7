#include "tools/sim/fault_injector.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <vector>

#include "drivers/mti/imu_recording_writer.hpp"
#include "drivers/pcap/pcap_file.hpp"
#include "drivers/pcap/udp_frame.hpp"
#include "drivers/rs16/lidar_datagram.hpp"
#include "drivers/rs16/packet_layout.hpp"
#include "tools/sim/header_time.hpp"
#include "tools/sim/pending_file.hpp"
#include "tools/sim/run_writer.hpp"
#include "tools/sim/sensor_rng.hpp"
#include "tools/sim/wire_faults.hpp"

namespace tumble::sim {
namespace {

namespace fs = std::filesystem;

// A duplicate or foreign datagram arrives just after the one it follows.
constexpr std::int64_t kFollowerDelayNs = 1000;

struct LidarRecord {
  std::int64_t t_ns = 0;
  std::vector<std::uint8_t> frame;
  std::optional<rs16::PacketKind> kind;  // nullopt: not lidar traffic, carried as it is
  std::size_t payload_offset = 0;        // of the UDP payload inside frame
  std::size_t payload_size = 0;
};

struct ImuRead {
  std::int64_t t_ns = 0;
  std::vector<std::uint8_t> bytes;
};

std::vector<LidarRecord> read_lidar(const fs::path& path) {
  pcap::Reader reader(path.string());
  if (reader.link_type() != pcap::kLinkEthernet)
    throw std::runtime_error(path.string() + ": not an Ethernet pcap (as `tumble-sim run` writes)");
  const rs16::SourceConfig ports;
  std::vector<LidarRecord> records;
  while (const auto r = reader.next()) {
    LidarRecord rec{r->t_ns, {r->bytes.begin(), r->bytes.end()}, std::nullopt, 0, 0};
    if (const auto udp = pcap::parse_udp_datagram(reader.link_type(), rec.frame)) {
      rec.kind = rs16::kind_for_port(ports, udp->dst_port);
      rec.payload_offset = static_cast<std::size_t>(udp->payload.data() - rec.frame.data());
      rec.payload_size = udp->payload.size();
    }
    records.push_back(std::move(rec));
  }
  if (reader.truncated()) throw std::runtime_error(reader.error());
  return records;
}

std::vector<ImuRead> read_imu(const fs::path& path) {
  pcap::Reader reader(path.string());
  if (reader.link_type() != pcap::kLinkUser0)
    throw std::runtime_error(path.string() + ": not an IMU recording (LINKTYPE_USER0)");
  std::vector<ImuRead> reads;
  while (const auto r = reader.next()) reads.push_back({r->t_ns, {r->bytes.begin(), r->bytes.end()}});
  if (reader.truncated()) throw std::runtime_error(reader.error());
  return reads;
}

std::int64_t to_ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

bool in_window(std::int64_t t_ns, std::int64_t start_ns, const std::optional<FaultWindow>& w) {
  if (!w) return false;
  const std::int64_t begin = start_ns + to_ns(w->start_s);
  return t_ns >= begin && t_ns < begin + to_ns(w->duration_s);
}

bool is_msop(const LidarRecord& r) { return r.kind == rs16::PacketKind::Msop; }

// Each fault draws once per source MSOP packet from its own stream, so adding
// one fault to a plan does not change which packets another one hits.
struct MsopDraws {
  bool drop, dup, swap, foreign;
  std::uint64_t foreign_pick;
};

// Late arrivals keep their order: a datagram never overtakes the one before.
void delay_lidar(std::vector<LidarRecord>& records, const FaultPlan& plan, FaultCounts& counts) {
  if (plan.lidar_delay_s <= 0.0) return;
  constexpr double kStallChance = 0.002;
  constexpr double kStallToMeanDelay = 4.0;
  SensorRng rng(plan.seed, "faults/lidar-delay");
  const auto exponential = [&rng](double mean_s) { return -mean_s * std::log(1.0 - rng.uniform()); };
  std::int64_t previous_ns = std::numeric_limits<std::int64_t>::min();
  std::int64_t stall_end_ns = std::numeric_limits<std::int64_t>::min();
  double delay_sum_s = 0.0;
  for (auto& r : records) {
    if (rng.chance(kStallChance)) {
      stall_end_ns = std::max(stall_end_ns, r.t_ns + to_ns(exponential(kStallToMeanDelay * plan.lidar_delay_s)));
      ++counts.lidar_stalls;
    }
    const std::int64_t arrival_ns =
        std::max({r.t_ns + to_ns(exponential(plan.lidar_delay_s)), stall_end_ns, previous_ns});
    const double delay_s = static_cast<double>(arrival_ns - r.t_ns) * 1e-9;
    if (arrival_ns > r.t_ns) ++counts.lidar_delayed;
    delay_sum_s += delay_s;
    counts.lidar_max_delay_s = std::max(counts.lidar_max_delay_s, delay_s);
    r.t_ns = previous_ns = arrival_ns;
  }
  if (!records.empty()) counts.lidar_mean_delay_s = delay_sum_s / static_cast<double>(records.size());
}

// The head stops where it was when the stall began; the lasers fire on.
void stall_motor(std::vector<LidarRecord>& records, std::int64_t start_ns, const FaultPlan& plan, FaultCounts& counts) {
  if (!plan.motor_stall) return;
  std::optional<std::uint16_t> held;
  for (auto& r : records) {
    if (!is_msop(r)) continue;
    const std::span<std::uint8_t> payload(r.frame.data() + r.payload_offset, r.payload_size);
    if (!in_window(r.t_ns, start_ns, plan.motor_stall)) {
      held.reset();
      continue;
    }
    if (!held) held = last_msop_azimuth(payload);
    counts.lidar_stalled += stall_msop_azimuths(payload, *held);
  }
}

void recalibrate(std::vector<LidarRecord>& records, std::int64_t start_ns, const FaultPlan& plan,
                 FaultCounts& counts) {
  if (!plan.difop_change_at_s) return;
  for (auto& r : records) {
    if (r.kind != rs16::PacketKind::Difop || r.t_ns < start_ns + to_ns(*plan.difop_change_at_s)) continue;
    counts.difop_recalibrated +=
        recalibrate_difop(std::span<std::uint8_t>(r.frame.data() + r.payload_offset, r.payload_size));
  }
}

// The lidar's own datagrams from the lead before the start, sent again from
// kForeignLidarIp kSecondLidarSpeedup times as fast, their header times
// moved to their new arrival, until the run ends.
void add_second_lidar(std::vector<LidarRecord>& records, std::int64_t start_ns, const FaultPlan& plan,
                      FaultCounts& counts) {
  if (!plan.second_lidar || records.empty()) return;
  const std::int64_t begin_ns = start_ns + to_ns(plan.second_lidar->at_s);
  const std::int64_t source_ns = begin_ns - to_ns(plan.second_lidar->lead_s);
  const std::int64_t end_ns = records.back().t_ns;
  std::vector<LidarRecord> copies;
  for (const auto& r : records) {
    if (!r.kind || r.t_ns < source_ns) continue;
    const auto t_ns = begin_ns + static_cast<std::int64_t>(static_cast<double>(r.t_ns - source_ns) / kSecondLidarSpeedup);
    if (t_ns > end_ns) break;
    std::vector<std::uint8_t> payload(r.frame.begin() + static_cast<std::ptrdiff_t>(r.payload_offset),
                                      r.frame.begin() + static_cast<std::ptrdiff_t>(r.payload_offset + r.payload_size));
    shift_header_time(payload, is_msop(r), t_ns - r.t_ns);
    const rs16::SourceConfig ports;
    const std::uint16_t port = is_msop(r) ? ports.msop_port : ports.difop_port;
    copies.push_back({t_ns, pcap::make_udp_ethernet_frame(kForeignLidarIp, kHostIp, port, port, payload), r.kind, 0,
                      payload.size()});
  }
  counts.lidar_second_sender = copies.size();
  const std::size_t before = records.size();
  records.insert(records.end(), std::make_move_iterator(copies.begin()), std::make_move_iterator(copies.end()));
  std::inplace_merge(records.begin(), records.begin() + static_cast<std::ptrdiff_t>(before), records.end(),
                     [](const LidarRecord& a, const LidarRecord& b) { return a.t_ns < b.t_ns; });
}

std::vector<LidarRecord> inject_lidar(std::vector<LidarRecord> in, std::int64_t start_ns, const FaultPlan& plan,
                                      FaultCounts& counts) {
  SensorRng drop_rng(plan.seed, "faults/drop-lidar"), dup_rng(plan.seed, "faults/dup-lidar"),
      swap_rng(plan.seed, "faults/swap-lidar"), foreign_rng(plan.seed, "faults/foreign-lidar");
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (is_msop(in[i])) ++counts.msop_packets;
    if (in[i].kind == rs16::PacketKind::Difop) ++counts.difop_packets;
  }
  // Kept records in order, each MSOP with its draws.
  std::vector<LidarRecord> kept;
  std::vector<std::optional<MsopDraws>> draws;
  const std::int64_t jump_ns = plan.lidar_clock_jump ? start_ns + to_ns(plan.lidar_clock_jump->at_s) : 0;
  for (auto& r : in) {
    std::optional<MsopDraws> d;
    if (is_msop(r)) {
      d = MsopDraws{drop_rng.chance(plan.drop_lidar), dup_rng.chance(plan.dup_lidar),
                    swap_rng.chance(plan.swap_lidar), foreign_rng.chance(plan.foreign_lidar),
                    foreign_rng.next_u64()};
    }
    if (r.kind && in_window(r.t_ns, start_ns, plan.lidar_gap)) {
      ++counts.lidar_gap_dropped;
      continue;
    }
    if (r.kind && plan.lidar_clock_jump && r.t_ns >= jump_ns &&
        shift_header_time(std::span<std::uint8_t>(r.frame.data() + r.payload_offset, r.payload_size), is_msop(r),
                          to_ns(plan.lidar_clock_jump->jump_s)))
      ++counts.lidar_clock_jumped;
    if (d && d->drop) {
      ++counts.lidar_dropped;
      continue;
    }
    kept.push_back(std::move(r));
    draws.push_back(d);
  }
  // Swaps exchange the contents of neighbouring MSOP packets; arrival times stay in order.
  std::optional<std::size_t> pending;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (!is_msop(kept[i])) continue;
    if (pending) {
      std::swap(kept[*pending].frame, kept[i].frame);
      std::swap(kept[*pending].payload_offset, kept[i].payload_offset);
      std::swap(kept[*pending].payload_size, kept[i].payload_size);
      ++counts.lidar_swapped_pairs;
      pending.reset();
    } else if (draws[i]->swap) {
      pending = i;
    }
  }
  std::vector<std::size_t> kept_msop;
  for (std::size_t i = 0; i < kept.size(); ++i)
    if (is_msop(kept[i])) kept_msop.push_back(i);
  std::vector<LidarRecord> out;
  out.reserve(kept.size() + kept.size() / 8);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    out.push_back(kept[i]);
    if (!draws[i]) continue;
    std::int64_t t_ns = kept[i].t_ns;
    if (draws[i]->dup) {
      LidarRecord copy = kept[i];
      copy.t_ns = t_ns += kFollowerDelayNs;
      out.push_back(std::move(copy));
      ++counts.lidar_duplicated;
    }
    if (draws[i]->foreign) {
      // Another sensor's traffic to the lidar port: a real MSOP packet of the
      // run, from elsewhere in it, sent from a foreign address.
      const LidarRecord& payload_of = kept[kept_msop[draws[i]->foreign_pick % kept_msop.size()]];
      const std::span<const std::uint8_t> payload(payload_of.frame.data() + payload_of.payload_offset,
                                                  payload_of.payload_size);
      const rs16::SourceConfig ports;
      LidarRecord foreign{t_ns + kFollowerDelayNs,
                          pcap::make_udp_ethernet_frame(kForeignLidarIp, kHostIp, ports.msop_port, ports.msop_port,
                                                        payload),
                          rs16::PacketKind::Msop, 0, payload.size()};
      out.push_back(std::move(foreign));
      ++counts.lidar_foreign;
    }
  }
  stall_motor(out, start_ns, plan, counts);
  recalibrate(out, start_ns, plan, counts);
  add_second_lidar(out, start_ns, plan, counts);
  delay_lidar(out, plan, counts);
  return out;
}

// Frames span serial reads: the reads are joined, poisoned, and cut again where they were.
void poison_imu(std::vector<ImuRead>& reads, const FaultPlan& plan, FaultCounts& counts) {
  if (plan.imu_nan <= 0.0) return;
  std::vector<std::uint8_t> stream;
  for (const auto& r : reads) stream.insert(stream.end(), r.bytes.begin(), r.bytes.end());
  SensorRng nan_rng(plan.seed, "faults/imu-nan");
  counts.imu_nan_frames = poison_rate_of_turn(stream, [&] { return nan_rng.chance(plan.imu_nan); });
  std::size_t at = 0;
  for (auto& r : reads) {
    std::copy_n(stream.begin() + static_cast<std::ptrdiff_t>(at), r.bytes.size(), r.bytes.begin());
    at += r.bytes.size();
  }
}

std::vector<ImuRead> inject_imu(std::vector<ImuRead> in, std::int64_t start_ns, const FaultPlan& plan,
                                FaultCounts& counts) {
  poison_imu(in, plan, counts);
  SensorRng garbage_rng(plan.seed, "faults/imu-garbage");
  counts.imu_reads = in.size();
  std::vector<ImuRead> out;
  out.reserve(in.size());
  for (auto& r : in) {
    const bool garble = garbage_rng.chance(plan.imu_garbage);
    const std::size_t n = 1 + static_cast<std::size_t>(garbage_rng.next_u64() % 40);
    if (in_window(r.t_ns, start_ns, plan.imu_gap)) {
      ++counts.imu_gap_dropped;
      continue;
    }
    if (garble) {
      std::vector<std::uint8_t> bytes(n);
      for (auto& b : bytes) b = static_cast<std::uint8_t>(garbage_rng.next_u64() >> 56);
      bytes.insert(bytes.end(), r.bytes.begin(), r.bytes.end());
      r.bytes = std::move(bytes);
      ++counts.imu_garbled_reads;
      counts.imu_garbage_bytes += n;
    }
    out.push_back(std::move(r));
  }
  return out;
}

void write_lidar(const std::vector<LidarRecord>& records, const fs::path& path) {
  PendingFile file(path);
  {
    pcap::Writer writer(file.temp().string(), pcap::kLinkEthernet);
    for (const auto& r : records) writer.write(r.t_ns, r.frame);
    writer.close();
  }
  file.commit();
}

void write_imu(const std::vector<ImuRead>& reads, const fs::path& path) {
  PendingFile file(path);
  {
    mti::ImuRecordingWriter writer(file.temp().string());
    for (const auto& r : reads) writer.write(r.t_ns, r.bytes);
    writer.close();
  }
  file.commit();
}

YAML::Node window_node(const FaultWindow& w, double run_start_s) {
  YAML::Node n;
  n["start_s"] = w.start_s;
  n["duration_s"] = w.duration_s;
  n["host_start_s"] = run_start_s + w.start_s;
  return n;
}

void write_record(const fs::path& run_dir, const FaultPlan& plan, const FaultCounts& c, const fs::path& path) {
  YAML::Node m;
  m["source_run"] = fs::absolute(run_dir).string();
  m["seed"] = plan.seed;
  m["run_start_s"] = YAML::Node(c.run_start_s);
  YAML::Node p;
  p["drop_lidar"] = plan.drop_lidar;
  p["dup_lidar"] = plan.dup_lidar;
  p["swap_lidar"] = plan.swap_lidar;
  p["foreign_lidar"] = plan.foreign_lidar;
  p["imu_garbage"] = plan.imu_garbage;
  p["imu_nan"] = plan.imu_nan;
  if (plan.motor_stall) p["motor_stall"] = window_node(*plan.motor_stall, c.run_start_s);
  if (plan.difop_change_at_s) p["difop_change_at_s"] = *plan.difop_change_at_s;
  if (plan.second_lidar) {
    p["second_lidar"]["at_s"] = plan.second_lidar->at_s;
    p["second_lidar"]["lead_s"] = plan.second_lidar->lead_s;
    p["second_lidar"]["host_at_s"] = c.run_start_s + plan.second_lidar->at_s;
  }
  p["lidar_delay_s"] = plan.lidar_delay_s;
  if (plan.lidar_gap) p["lidar_gap"] = window_node(*plan.lidar_gap, c.run_start_s);
  if (plan.imu_gap) p["imu_gap"] = window_node(*plan.imu_gap, c.run_start_s);
  if (plan.lidar_clock_jump) {
    p["lidar_clock_jump"]["at_s"] = plan.lidar_clock_jump->at_s;
    p["lidar_clock_jump"]["jump_s"] = plan.lidar_clock_jump->jump_s;
    p["lidar_clock_jump"]["host_at_s"] = c.run_start_s + plan.lidar_clock_jump->at_s;
  }
  m["plan"] = p;
  YAML::Node n;
  n["msop_packets"] = c.msop_packets;
  n["difop_packets"] = c.difop_packets;
  n["lidar_gap_dropped"] = c.lidar_gap_dropped;
  n["lidar_clock_jumped"] = c.lidar_clock_jumped;
  n["lidar_dropped"] = c.lidar_dropped;
  n["lidar_duplicated"] = c.lidar_duplicated;
  n["lidar_swapped_pairs"] = c.lidar_swapped_pairs;
  n["lidar_foreign"] = c.lidar_foreign;
  n["lidar_delayed"] = c.lidar_delayed;
  n["lidar_stalls"] = c.lidar_stalls;
  n["lidar_mean_delay_s"] = c.lidar_mean_delay_s;
  n["lidar_max_delay_s"] = c.lidar_max_delay_s;
  n["imu_reads"] = c.imu_reads;
  n["imu_gap_dropped"] = c.imu_gap_dropped;
  n["imu_garbled_reads"] = c.imu_garbled_reads;
  n["imu_garbage_bytes"] = c.imu_garbage_bytes;
  n["imu_nan_frames"] = c.imu_nan_frames;
  n["lidar_stalled"] = c.lidar_stalled;
  n["lidar_second_sender"] = c.lidar_second_sender;
  n["difop_recalibrated"] = c.difop_recalibrated;
  m["injected"] = n;
  PendingFile file(path);
  {
    std::ofstream out(file.temp());
    YAML::Emitter e;
    e.SetDoublePrecision(17);
    e << m;
    out << e.c_str() << "\n";
    if (!out) throw std::runtime_error(path.string() + ": write failed");
  }
  file.commit();
}

}  // namespace

FaultCounts inject_faults(const fs::path& run_dir, const fs::path& out_dir, const FaultPlan& plan) {
  validate(plan);
  if (!fs::is_directory(run_dir)) throw std::invalid_argument(run_dir.string() + ": not a run folder");
  for (const char* name : {kLidarPcapName, kImuPcapName, kGroundTruthName, kManifestName}) {
    if (!fs::is_regular_file(run_dir / name))
      throw std::invalid_argument(run_dir.string() + ": not a run folder (no " + name + ")");
  }
  if (fs::exists(out_dir) && fs::equivalent(run_dir, out_dir))
    throw std::invalid_argument(out_dir.string() + ": OUT_DIR must differ from RUN_DIR");
  auto lidar = read_lidar(run_dir / kLidarPcapName);
  auto imu = read_imu(run_dir / kImuPcapName);
  std::int64_t start_ns = std::numeric_limits<std::int64_t>::max();
  if (!lidar.empty()) start_ns = lidar.front().t_ns;
  if (!imu.empty()) start_ns = std::min(start_ns, imu.front().t_ns);
  if (lidar.empty() && imu.empty()) throw std::invalid_argument(run_dir.string() + ": both recordings are empty");

  FaultCounts counts;
  counts.run_start_s = static_cast<double>(start_ns) * 1e-9;
  lidar = inject_lidar(std::move(lidar), start_ns, plan, counts);
  imu = inject_imu(std::move(imu), start_ns, plan, counts);

  fs::create_directories(out_dir);
  write_lidar(lidar, out_dir / kLidarPcapName);
  write_imu(imu, out_dir / kImuPcapName);
  for (const char* name : {kGroundTruthName, kManifestName})
    fs::copy_file(run_dir / name, out_dir / name, fs::copy_options::overwrite_existing);
  write_record(run_dir, plan, counts, out_dir / kFaultsName);
  return counts;
}

}  // namespace tumble::sim
