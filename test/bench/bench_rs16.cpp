// RS-16 decode + scan assembly throughput on one core, packets/s. The input
// is a generated 10 s stream (7500 MSOP packets, 600 rpm, varied ranges with
// some no-returns), fed through the same path as live data (Driver).
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <spdlog/spdlog.h>
#include <vector>

#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/msop_encode.hpp"

namespace {

using namespace tumble::rs16;

constexpr int kPackets = 7500;
constexpr std::int64_t kT0Ns = 1'704'067'200'000'000'000;
constexpr double kPacket_s = 1332e-6;

std::vector<std::array<std::uint8_t, 1248>> make_stream() {
  std::vector<std::array<std::uint8_t, 1248>> packets;
  packets.reserve(kPackets);
  const double step_deg = 600.0 * 6.0 * 111e-6;
  for (int i = 0; i < kPackets; ++i) {
    MsopPacketData p;
    p.utc_time_ns = kT0Ns + static_cast<std::int64_t>(std::llround(i * kPacket_s * 1e9));
    for (int b = 0; b < 12; ++b) {
      const double azimuth_deg = std::fmod(step_deg * (i * 12 + b), 360.0);
      p.blocks[b].azimuth_deg = azimuth_deg;
      for (int c = 0; c < 32; ++c) {
        // A room-like range profile; every 37th return missing.
        const int k = (i * 12 + b) * 32 + c;
        const double range_m = 3.0 + 8.0 * std::abs(std::sin(azimuth_deg * 0.0349)) + 0.1 * (c % 16);
        p.blocks[b].channels[c] = {k % 37 == 0 ? 0.0 : range_m, static_cast<std::uint8_t>(k)};
      }
    }
    packets.push_back(encode_msop(p));
  }
  return packets;
}

const std::vector<std::array<std::uint8_t, 1248>>& stream() {
  static const auto packets = make_stream();
  return packets;
}

void run(benchmark::State& state, ClockMode clock) {
  spdlog::set_level(spdlog::level::warn);
  const auto& packets = stream();
  DifopData difop;
  for (int i = 0; i < 16; ++i) difop.vertical_angles_deg[i] = (i < 8 ? -1.0 : 1.0) * (15.0 - 2.0 * (i % 8)) + 0.0042;
  const auto difop_bytes = encode_difop(difop);
  DriverConfig config;
  config.decoder.clock = clock;
  std::size_t points = 0;
  Driver driver(config, [&](tumble::Scan& scan, const ScanReport&) { points += scan.points.size(); });
  driver.on_datagram({PacketKind::Difop, kT0Ns * 1e-9, 0, difop_bytes});
  std::int64_t n = 0;
  // Arrival times keep running forward over the passes; header times repeat, so
  // with a synced clock each pass (7500 packets) starts a fresh scan.
  double lap_s = 0.0;
  for (auto _ : state) {
    const std::size_t i = static_cast<std::size_t>(n % kPackets);
    if (i == 0 && n > 0) lap_s += kPackets * kPacket_s;
    driver.on_datagram({PacketKind::Msop, kT0Ns * 1e-9 + lap_s + i * kPacket_s + 0.0015, 0, packets[i]});
    ++n;
  }
  benchmark::DoNotOptimize(points);
  state.SetItemsProcessed(n);
  state.counters["scans"] = static_cast<double>(driver.stats().scans);
}

void BM_Rs16DecodeAndAssemble(benchmark::State& state) { run(state, ClockMode::Synced); }
void BM_Rs16DecodeAndAssembleFreeClock(benchmark::State& state) { run(state, ClockMode::Free); }

}  // namespace

BENCHMARK(BM_Rs16DecodeAndAssemble);
BENCHMARK(BM_Rs16DecodeAndAssembleFreeClock);
BENCHMARK_MAIN();
