// Real frames from an MTi-300 (Scottapotamas/xsens-mti tests). Expected values
// are MT Manager's decode, as printed in that project's test comments; the
// tolerance is half a unit of the last printed digit.
#include <gtest/gtest.h>

#include <sstream>

#include "drivers/mti/commands.hpp"
#include "drivers/mti/imu_sample.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_decode.hpp"
#include "drivers/mti/output_configuration.hpp"
#include "test/drivers/mti/mti_test_util.hpp"
#include "test/fixtures.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr double k8 = 5.1e-9;   // 8 printed decimals
constexpr double k7 = 5.1e-8;   // 7 printed decimals

test_util::OwnedFrame only_frame(const std::string& name) {
  const Bytes bytes = test_util::read_file(test::fixture_path("mti/mti-300-frames/" + name + ".bin"));
  FrameReader reader;
  auto frames = test_util::read_frames(reader, bytes);
  EXPECT_EQ(frames.size(), 1u) << name;
  EXPECT_EQ(reader.stats().bytes_discarded, 0u) << name;
  return frames.empty() ? test_util::OwnedFrame{} : frames[0];
}

MtData2 decoded(const std::string& name) {
  const auto frame = only_frame(name);
  EXPECT_EQ(frame.mid, mid::kMtData2);
  MtData2 m;
  MtData2DecodeStats stats;
  EXPECT_TRUE(decode_mtdata2(frame.payload, m, stats)) << name;
  EXPECT_EQ(stats.size_mismatches + stats.unknown_packets, 0u) << name;
  return m;
}

void expect_near(const std::optional<Eigen::Vector3d>& v, const Eigen::Vector3d& expected, double tol) {
  ASSERT_TRUE(v);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR((*v)[i], expected[i], tol) << "axis " << i;
}

void expect_near(const std::optional<std::array<double, 4>>& q, const std::array<double, 4>& expected, double tol) {
  ASSERT_TRUE(q);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR((*q)[i], expected[i], tol) << "component " << i;
}

TEST(Mti300Frames, EveryListedFrameIsItsFileAndReadsAsOneFrame) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/frames.txt");
  const auto lines = test_util::read_lines(test::fixture_path("mti/mti-300-frames/frames.txt"));
  ASSERT_EQ(lines.size(), 16u);
  for (const std::string& line : lines) {
    std::istringstream fields(line);
    std::string name, hex;
    fields >> name >> hex;
    const Bytes bytes = test_util::from_hex(hex);
    EXPECT_EQ(bytes, test_util::read_file(test::fixture_path("mti/mti-300-frames/" + name + ".bin"))) << name;
    const auto frame = only_frame(name);
    EXPECT_EQ(frame.frame_bytes, bytes.size()) << name;
    EXPECT_EQ(encode_xbus_frame(frame.mid, frame.payload, frame.bus_id), bytes) << name;
  }
}

TEST(Mti300Frames, RepliesToConfigurationCommands) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/frames.txt");
  EXPECT_EQ(only_frame("test_parse_GoToConfigAck").mid, mid::kGoToConfigAck);
  EXPECT_EQ(only_frame("test_parse_GotoMeasurementAck").mid, mid::kGoToMeasurementAck);
  EXPECT_EQ(only_frame("test_parse_StringOutputType").mid, 0x8F);
  const auto config = only_frame("test_parse_OutputConfiguration");
  EXPECT_EQ(config.mid, mid::kOutputConfiguration);
  EXPECT_EQ(parse_output_configuration(config.payload),
            (std::vector<OutputSetting>{{0x1020, 0xFFFF}, {0x1060, 0xFFFF}}));
  const auto init = only_frame("test_parse_InitMTResults");
  EXPECT_EQ(parse_device_id(init.payload), 0x037003F8u);
  const auto fw = parse_firmware_revision(only_frame("test_parse_FirmwareRev").payload);
  ASSERT_TRUE(fw);
  EXPECT_EQ(fw->text(), "1.8.2 build 37 rev 70964");
  const auto configuration = only_frame("test_parse_Configuration");
  EXPECT_EQ(configuration.mid, 0x0D);
  ASSERT_EQ(configuration.payload.size(), 118u);
  EXPECT_EQ(parse_device_id(std::span(configuration.payload).first(4)), 0x037003F8u);
}

TEST(Mti300Frames, QuaternionOnlyMessageIsNoImuSample) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/test_parse_mdata2_quat_minimal.bin");
  const MtData2 m = decoded("test_parse_mdata2_quat_minimal");
  EXPECT_EQ(m.packet_counter, 18050);
  EXPECT_EQ(m.sample_time_fine, 29686846u);
  expect_near(m.quaternion, {0.94455600, -0.32308814, 0.01374718, -0.05691256}, k8);
  EXPECT_EQ(m.status_word, 0b00000000010000000000000000000011u);
  EXPECT_FALSE(has_imu_data(m));
}

TEST(Mti300Frames, FullMessage) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/test_parse_mdata2_full.bin");
  const MtData2 m = decoded("test_parse_mdata2_full");
  EXPECT_EQ(m.packet_counter, 37261);
  EXPECT_EQ(m.sample_time_fine, 20332454u);
  expect_near(m.quaternion, {0.71045315, 0.69453555, -0.07777759, -0.08262789}, k8);
  expect_near(m.acceleration_m_s2, {-0.05550629, 9.81465530, 0.21842313}, k8);
  expect_near(m.delta_v_m_s, {-0.00013867, 0.02453661, 0.00054736}, k8);
  expect_near(m.free_acceleration_m_s2, {-0.01142347, 0.01110744, 0.02007198}, k8);
  expect_near(m.rate_of_turn_rad_s, {0.02131760, -0.00327826, -0.00163019}, k8);
  expect_near(m.delta_q, {1.00000000, 0.00002665, -0.00000410, -0.00000204}, k8);
  expect_near(m.magnetic_field_au, {-0.49215657, 0.70221740, -1.25496686}, k8);
  EXPECT_EQ(m.temperature_c, 37.625);
  EXPECT_EQ(m.baro_pressure_pa, 100065u);
  EXPECT_EQ(m.status_word, 0b00000000010000000000000000000011u);
  ImuSample s;
  ASSERT_TRUE(fill_imu_sample(m, 0.01, s));
  EXPECT_TRUE(s.has_orientation);
  EXPECT_NEAR(s.orientation.w(), 0.71045315, k8);
  EXPECT_NEAR(s.orientation.x(), 0.69453555, k8);
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(s.accel_saturated[i] || s.gyro_saturated[i]);
}

// Shaken hard: the fixture's StatusWord 0x00481401 sets bit 10 (accel Z),
// bit 12 (gyro Y) and bit 19 (any clipping); gyro Y reads -10.33 rad/s from
// a 450 deg/s (7.85 rad/s) gyroscope.
TEST(Mti300Frames, ShakeClippingFlagsGyroYAndAccelZ) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/test_parse_mdata2_shake_clipping.bin");
  const MtData2 m = decoded("test_parse_mdata2_shake_clipping");
  EXPECT_EQ(m.packet_counter, 64389);
  EXPECT_EQ(m.sample_time_fine, 27564254u);
  expect_near(m.quaternion, {0.66437358, -0.42175028, 0.02720882, 0.61643654}, k8);
  expect_near(m.acceleration_m_s2, {-30.28455162, -29.60960007, -71.76024628}, k8);
  expect_near(m.delta_v_m_s, {-0.07186279, -0.07130830, -0.18206376}, k8);
  expect_near(m.free_acceleration_m_s2, {52.39491272, -62.83823395, -25.59408188}, k8);
  expect_near(m.rate_of_turn_rad_s, {4.16570139, -10.33340263, -4.51734877}, k8);
  expect_near(m.delta_q, {0.99988699, 0.00520693, -0.01291627, -0.00564647}, k8);
  expect_near(m.magnetic_field_au, {0.43057421, -0.23942292, 1.37189472}, k8);
  EXPECT_EQ(m.baro_pressure_pa, 100062u);
  EXPECT_EQ(m.status_word, 0b00000000010010000001010000000001u);
  ImuSample s;
  ASSERT_TRUE(fill_imu_sample(m, 0.0025, s));
  EXPECT_EQ(s.accel_saturated, (std::array<bool, 3>{false, false, true}));
  EXPECT_EQ(s.gyro_saturated, (std::array<bool, 3>{false, true, false}));
  EXPECT_TRUE(*m.status_word & kStatusClipAny);
  EXPECT_NEAR(s.gyro_rad_s.y(), -10.33340263, k8);
}

TEST(Mti300Frames, FixedPointAndDoubleFormats) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/test_parse_mdata2_number_formats.bin");
  const MtData2 m = decoded("test_parse_mdata2_number_formats");
  EXPECT_EQ(m.packet_counter, 15325);
  EXPECT_EQ(m.orientation_xdi, 0x2031);  // EulerAngles, Fp12.20, ENU
  expect_near(m.euler_angles_deg, {-0.9826155, -0.1385441, 115.7006302}, k7);
  expect_near(m.delta_q, {1.000000000233, -0.000429107808, -0.000302935718, -0.000177090988}, 5.1e-13);
  expect_near(m.magnetic_field_au, {0.833747744560242, -0.434182971715927, 1.617681622505188}, 5.1e-16);
  EXPECT_EQ(m.temperature_c, 27.4375);
}

// MT Manager shows the pressure as Float64 (XDI 0x3013), but the payload is
// the usual 4-byte u32: the format bits do not apply to integer outputs.
TEST(Mti300Frames, FixedPointAndDoubleFormats2) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/test_parse_mdata2_number_formats_2.bin");
  const MtData2 m = decoded("test_parse_mdata2_number_formats_2");
  EXPECT_EQ(m.packet_counter, 65144);
  expect_near(m.quaternion, {0.6447144, -0.00622723, -0.00247884, 0.7643942}, k7);
  expect_near(m.magnetic_field_au, {0.9619465, -0.2602215, 1.7812529}, k7);
  EXPECT_EQ(m.temperature_c, 24.375);
  EXPECT_EQ(m.baro_pressure_pa, 101669u);
}

// No reference values for these: a rotation matrix decoded with the wrong
// layout or byte order is not orthonormal.
TEST(Mti300Frames, RotationMatricesAreOrthonormalInEveryFormat) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/test_parse_mdata2_rotmatrix_float.bin");
  for (const std::string format : {"float", "fp1220", "fp1632", "double"}) {
    const MtData2 m = decoded("test_parse_mdata2_rotmatrix_" + format);
    ASSERT_TRUE(m.rotation_matrix) << format;
    const Eigen::Map<const Eigen::Matrix3d> r(m.rotation_matrix->data());
    EXPECT_LT((r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 5e-6) << format;
    EXPECT_NEAR(r.determinant(), 1.0, 5e-6) << format;
  }
}

TEST(Mti300Frames, AllFramesInOneDirtyStream) {
  TUMBLE_REQUIRE_FIXTURE("mti/mti-300-frames/frames.txt");
  Bytes stream{0x00, 0xFA, 0x13};
  std::size_t framed = 0;
  for (const std::string& line : test_util::read_lines(test::fixture_path("mti/mti-300-frames/frames.txt"))) {
    const Bytes frame = test_util::from_hex(line.substr(line.find(' ') + 1));
    framed += frame.size();
    test_util::append(stream, frame);
    test_util::append(stream, Bytes{0x55, 0xFA});
  }
  FrameReader reader;
  const auto frames = test_util::read_frames(reader, stream, 13);
  EXPECT_EQ(frames.size(), 16u);
  EXPECT_EQ(reader.stats().bytes_discarded, stream.size() - framed - reader.buffered_bytes());
}

}  // namespace
}  // namespace tumble::mti
