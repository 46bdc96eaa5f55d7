// The per-packet path (decode, clock map, scan assembly) must not allocate
// once running. Counts every operator new of this test binary's thread.
#include <gtest/gtest.h>

#include <cstdlib>
#include <new>
#include <vector>

#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/driver.hpp"
#include "test/drivers/rs16/packet_stream.hpp"

namespace {
thread_local std::size_t g_allocations = 0;
}

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace tumble::rs16 {
namespace {

TEST(Rs16NoAllocation, SteadyStateDecodingAndAssemblyDoNotAllocate) {
  for (const ClockMode clock : {ClockMode::Synced, ClockMode::Free}) {
    std::vector<std::array<std::uint8_t, 1248>> packets;
    for (int i = 0; i < 600; ++i) packets.push_back(encode_msop(test::stream_packet({}, i)));
    DifopData difop;
    for (int i = 0; i < 16; ++i) difop.vertical_angles_deg[i] = kDesignVerticalAnglesDeg[i];
    const auto difop_bytes = encode_difop(difop);

    DriverConfig config;
    config.decoder.clock = clock;
    std::size_t scans = 0;
    Driver driver(config, [&](Scan&, const ScanReport&) { ++scans; });
    const double t0 = test::StreamSpec{}.start_ns * 1e-9;
    auto feed = [&](int from, int to) {
      for (int i = from; i < to; ++i) {
        driver.on_datagram({PacketKind::Msop, t0 + i * 1332e-6 + 0.002, 0, packets[static_cast<std::size_t>(i)]});
        if (i % 100 == 0) driver.on_datagram({PacketKind::Difop, t0 + i * 1332e-6, 0, difop_bytes});
      }
    };
    feed(0, 200);
    const std::size_t scans_before = scans;
    const std::size_t before = g_allocations;
    feed(200, 600);
    EXPECT_EQ(g_allocations - before, 0u) << (clock == ClockMode::Free ? "free" : "synced") << " clock";
    EXPECT_GE(scans - scans_before, 5u);
    EXPECT_EQ(driver.stats().msop_packets, 600u);
  }
}

}  // namespace
}  // namespace tumble::rs16
