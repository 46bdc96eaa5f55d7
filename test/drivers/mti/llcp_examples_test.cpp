// The example frames printed in Xsens' low-level protocol document.
#include <gtest/gtest.h>

#include "drivers/mti/commands.hpp"
#include "drivers/mti/imu_sample.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_decode.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "drivers/mti/xdi.hpp"
#include "test/drivers/mti/mti_test_util.hpp"
#include "test/fixtures.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;

const std::vector<OutputSetting> kLlcpOutputs{
    {0x1020, 0xFFFF}, {0x1060, 0xFFFF}, {0x2010, 100}, {0x4020, 400}, {0x8020, 400}, {0xC020, 100},
    {0xE020, 0xFFFF}, {0x5042, 100},    {0x5022, 100}, {0xD012, 100}};

test_util::OwnedFrame only_frame(const Bytes& bytes) {
  const auto frames = test_util::read_frames(bytes);
  EXPECT_EQ(frames.size(), 1u);
  return frames.empty() ? test_util::OwnedFrame{} : frames[0];
}

TEST(LlcpExamples, SetOutputConfigurationIsWhatOurEncoderWrites) {
  TUMBLE_REQUIRE_FIXTURE("mti/llcp-examples/llcp_example_SetOutputConfiguration.bin");
  const Bytes bytes = test_util::read_file(test::fixture_path("mti/llcp-examples/llcp_example_SetOutputConfiguration.bin"));
  const auto frame = only_frame(bytes);
  EXPECT_EQ(frame.mid, mid::kSetOutputConfiguration);
  EXPECT_EQ(parse_output_configuration(frame.payload), kLlcpOutputs);
  EXPECT_EQ(encode_set_output_configuration(kLlcpOutputs), bytes);
}

TEST(LlcpExamples, OutputConfigurationAckEchoesTheList) {
  TUMBLE_REQUIRE_FIXTURE("mti/llcp-examples/llcp_example_SetOutputConfigurationAck.bin");
  const auto frame =
      only_frame(test_util::read_file(test::fixture_path("mti/llcp-examples/llcp_example_SetOutputConfigurationAck.bin")));
  EXPECT_EQ(frame.mid, mid::kOutputConfiguration);
  EXPECT_EQ(parse_output_configuration(frame.payload), kLlcpOutputs);
  EXPECT_EQ(describe(parse_output_configuration(frame.payload)),
            "PacketCounter@max, SampleTimeFine@max, Quaternion(EastNorthUp,Float32)@100Hz, "
            "Acceleration(Float32)@400Hz, RateOfTurn(Float32)@400Hz, MagneticField(Float32)@100Hz, StatusWord@max, "
            "LatLon(Fp1632)@100Hz, AltitudeEllipsoid(Fp1632)@100Hz, VelocityXYZ(EastNorthUp,Fp1632)@100Hz");
}

// PacketCounter, SampleTimeFine, Acceleration, RateOfTurn, StatusWord in
// Float32: exactly what encode_mtdata2 writes, so re-encoding the decoded
// values must give the document's bytes back.
TEST(LlcpExamples, MtData2ExampleDecodesAndReencodesByteForByte) {
  TUMBLE_REQUIRE_FIXTURE("mti/llcp-examples/llcp_example_mtdata2_PC_STF_Acc_RoT_SW.bin");
  const Bytes bytes =
      test_util::read_file(test::fixture_path("mti/llcp-examples/llcp_example_mtdata2_PC_STF_Acc_RoT_SW.bin"));
  const auto frame = only_frame(bytes);
  ASSERT_EQ(frame.mid, mid::kMtData2);
  MtData2 m;
  MtData2DecodeStats stats;
  ASSERT_TRUE(decode_mtdata2(frame.payload, m, stats));
  EXPECT_EQ(m.packet_counter, 57285);
  EXPECT_EQ(m.sample_time_fine, 4562336u);
  EXPECT_EQ(m.status_word, 0x81u);
  ASSERT_TRUE(m.acceleration_m_s2 && m.rate_of_turn_rad_s);
  EXPECT_NEAR(m.acceleration_m_s2->norm(), 9.81, 0.05);  // at rest
  EXPECT_LT(m.rate_of_turn_rad_s->norm(), 0.01);

  MtData2Out out;
  out.packet_counter = *m.packet_counter;
  out.sample_time_fine = *m.sample_time_fine;
  out.accel_m_s2 = *m.acceleration_m_s2;
  out.gyro_rad_s = *m.rate_of_turn_rad_s;
  out.status_word = *m.status_word;
  EXPECT_EQ(encode_xbus_frame(mid::kMtData2, encode_mtdata2(out)), bytes);

  ImuSample s;
  ASSERT_TRUE(fill_imu_sample(m, 0.0025, s));
  EXPECT_EQ(s.accel_m_s2, *m.acceleration_m_s2);
  EXPECT_FALSE(s.has_orientation);
}

}  // namespace
}  // namespace tumble::mti
