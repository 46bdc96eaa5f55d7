#include "drivers/mti/xbus_frame.hpp"

#include <gtest/gtest.h>

#include <numeric>

#include "drivers/mti/commands.hpp"
#include "drivers/mti/message_ids.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(XbusFrame, EmptyCommandsMatchTheProtocolDocument) {
  EXPECT_EQ(encode_go_to_config(), (Bytes{0xFA, 0xFF, 0x30, 0x00, 0xD1}));
  EXPECT_EQ(encode_req_device_id(), (Bytes{0xFA, 0xFF, 0x00, 0x00, 0x01}));
  EXPECT_EQ(encode_req_product_code(), (Bytes{0xFA, 0xFF, 0x1C, 0x00, 0xE5}));
  EXPECT_EQ(encode_req_firmware_rev(), (Bytes{0xFA, 0xFF, 0x12, 0x00, 0xEF}));
  EXPECT_EQ(encode_go_to_measurement(), (Bytes{0xFA, 0xFF, 0x10, 0x00, 0xF1}));
  EXPECT_EQ(encode_wake_up_ack(), (Bytes{0xFA, 0xFF, 0x3F, 0x00, 0xC2}));
  EXPECT_EQ(encode_xbus_frame(mid::kWakeUp, {}), (Bytes{0xFA, 0xFF, 0x3E, 0x00, 0xC3}));
}

TEST(XbusFrame, ChecksumMakesEverythingAfterThePreambleSumToZero) {
  Bytes payload(200);
  std::iota(payload.begin(), payload.end(), 7);
  for (const std::uint8_t bus : {kBusIdMaster, kBusIdFirstDevice}) {
    const Bytes frame = encode_xbus_frame(0x36, payload, bus);
    ASSERT_EQ(frame.size(), 4 + payload.size() + 1);
    EXPECT_EQ(frame[1], bus);
    EXPECT_EQ(std::accumulate(frame.begin() + 1, frame.end(), 0u) % 256, 0u);
  }
}

TEST(XbusFrame, PayloadsAbove254BytesUseTheExtendedLength) {
  for (const std::size_t n : {std::size_t{254}, std::size_t{255}, std::size_t{2048}}) {
    const Bytes frame = encode_xbus_frame(0x36, Bytes(n, 0xAB));
    if (n <= 254) {
      EXPECT_EQ(frame[3], n);
      EXPECT_EQ(frame.size(), n + 5);
    } else {
      EXPECT_EQ(frame[3], 0xFF);
      EXPECT_EQ((frame[4] << 8) | frame[5], static_cast<int>(n));
      EXPECT_EQ(frame.size(), n + 7);
    }
    EXPECT_EQ(std::accumulate(frame.begin() + 1, frame.end(), 0u) % 256, 0u);
  }
}

TEST(XbusFrame, PayloadAbove2048BytesIsRefused) {
  EXPECT_THROW(encode_xbus_frame(0x36, Bytes(2049)), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::mti
