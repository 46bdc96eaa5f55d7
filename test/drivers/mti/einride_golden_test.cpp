// Value-for-value equality with the goldens of einride/xsens-go (an
// independent Go decoder) on 100 real MTi-G-710 frames per number format.
// Every format is exact in a double (Fp16.32 has 48 significant bits) and Go
// prints the shortest text that reads back to the same double, so the
// comparison is exact (tolerance 0) for all four formats.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <map>

#include "drivers/mti/imu_sample.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_decode.hpp"
#include "drivers/mti/mtdata2_packets.hpp"
#include "drivers/mti/mti_stream.hpp"
#include "drivers/mti/output_configuration.hpp"
#include "drivers/mti/xdi.hpp"
#include "test/drivers/mti/golden_file.hpp"
#include "test/fixtures.hpp"

namespace tumble::mti {
namespace {

using test_util::GoldenMessage;
using test_util::GoldenSection;

std::string fixture_dir(int n) { return "mti/einride-mti-g-710/" + std::to_string(n) + "/"; }

bool same_text_ignoring_case(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

// "EulerAngles(EastNorthUp,Fp1632)" from our XDI table; Go spells the names
// in other case ("UTCTime", "FP1632") only.
std::string header_of(std::uint16_t xdi, bool with_format) {
  const auto info = xdi::info(xdi);
  if (!info) return "unknown";
  std::string h(info->name);
  if (with_format && info->layout == xdi::Layout::Reals) {
    h += "(";
    if (info->has_coordinate_system) h += std::string(xdi::coordinate_system_name(xdi::coordinate_system_of(xdi))) + ",";
    h += std::string(number_format_name(number_format_of(xdi))) + ")";
  }
  return h;
}

std::vector<double> reals_of(const MtData2& m, std::uint16_t type) {
  const auto v3 = [](const std::optional<Eigen::Vector3d>& v) {
    return v ? std::vector<double>{v->x(), v->y(), v->z()} : std::vector<double>{};
  };
  const auto arr = [](const auto& a) { return a ? std::vector<double>(a->begin(), a->end()) : std::vector<double>{}; };
  switch (type) {
    case xdi::kTemperature: return m.temperature_c ? std::vector<double>{*m.temperature_c} : std::vector<double>{};
    case xdi::kQuaternion: return arr(m.quaternion);
    case xdi::kRotationMatrix: return arr(m.rotation_matrix);
    case xdi::kEulerAngles: return v3(m.euler_angles_deg);
    case xdi::kDeltaV: return v3(m.delta_v_m_s);
    case xdi::kAcceleration: return v3(m.acceleration_m_s2);
    case xdi::kFreeAcceleration: return v3(m.free_acceleration_m_s2);
    case xdi::kAltitudeEllipsoid:
      return m.altitude_ellipsoid_m ? std::vector<double>{*m.altitude_ellipsoid_m} : std::vector<double>{};
    case xdi::kPositionEcef: return v3(m.position_ecef_m);
    case xdi::kLatLon: return arr(m.lat_lon_deg);
    case xdi::kRateOfTurn: return v3(m.rate_of_turn_rad_s);
    case xdi::kDeltaQ: return arr(m.delta_q);
    case xdi::kMagneticField: return v3(m.magnetic_field_au);
    case xdi::kVelocityXyz: return v3(m.velocity_m_s);
    default: return {};
  }
}

std::vector<std::string> keys_for(std::size_t count) {
  switch (count) {
    case 1: return {""};
    case 2: return {"Lat", "Lon"};
    case 3: return {"X", "Y", "Z"};
    case 4: return {"Q0", "Q1", "Q2", "Q3"};
    case 9: return {"A", "B", "C", "D", "E", "F", "G", "H", "I"};
    default: return {};
  }
}

std::string binary(std::uint32_t v, int bits) {
  std::string s;
  for (int b = bits - 1; b >= 0; --b) s += ((v >> b) & 1u) ? '1' : '0';
  return s;
}

// "2019-01-20T13:47:24.1219Z" (Go's RFC 3339, trailing zeros trimmed).
UtcTime parse_utc(const std::string& text) {
  UtcTime t;
  t.year = static_cast<std::uint16_t>(std::stoi(text.substr(0, 4)));
  t.month = static_cast<std::uint8_t>(std::stoi(text.substr(5, 2)));
  t.day = static_cast<std::uint8_t>(std::stoi(text.substr(8, 2)));
  t.hour = static_cast<std::uint8_t>(std::stoi(text.substr(11, 2)));
  t.minute = static_cast<std::uint8_t>(std::stoi(text.substr(14, 2)));
  t.second = static_cast<std::uint8_t>(std::stoi(text.substr(17, 2)));
  if (text[19] == '.') {
    std::string digits = text.substr(20, text.size() - 21);
    digits.resize(9, '0');
    t.nanosecond = static_cast<std::uint32_t>(std::stoul(digits));
  }
  return t;
}

using IntField = std::function<std::int64_t(const GnssPvt&)>;
const std::map<std::string, IntField>& pvt_fields() {
  static const std::map<std::string, IntField> fields{
      {"ITOW", [](const GnssPvt& g) { return g.itow_ms; }},
      {"Year", [](const GnssPvt& g) { return g.year; }},
      {"Month", [](const GnssPvt& g) { return g.month; }},
      {"Day", [](const GnssPvt& g) { return g.day; }},
      {"Hour", [](const GnssPvt& g) { return g.hour; }},
      {"Min", [](const GnssPvt& g) { return g.minute; }},
      {"Sec", [](const GnssPvt& g) { return g.second; }},
      {"Valid", [](const GnssPvt& g) { return g.valid; }},
      {"TAcc", [](const GnssPvt& g) { return g.time_accuracy_ns; }},
      {"Nano", [](const GnssPvt& g) { return g.nano_ns; }},
      {"FixType", [](const GnssPvt& g) { return g.fix_type; }},
      {"Flags", [](const GnssPvt& g) { return g.flags; }},
      {"NumSV", [](const GnssPvt& g) { return g.satellites; }},
      {"Reserved1", [](const GnssPvt& g) { return g.reserved1; }},
      {"Lon", [](const GnssPvt& g) { return g.lon_1e7_deg; }},
      {"Lat", [](const GnssPvt& g) { return g.lat_1e7_deg; }},
      {"Height", [](const GnssPvt& g) { return g.height_mm; }},
      {"HMSL", [](const GnssPvt& g) { return g.height_msl_mm; }},
      {"HAcc", [](const GnssPvt& g) { return g.horizontal_accuracy_mm; }},
      {"VAcc", [](const GnssPvt& g) { return g.vertical_accuracy_mm; }},
      {"VelN", [](const GnssPvt& g) { return g.vel_n_mm_s; }},
      {"VelE", [](const GnssPvt& g) { return g.vel_e_mm_s; }},
      {"VelD", [](const GnssPvt& g) { return g.vel_d_mm_s; }},
      {"GSpeed", [](const GnssPvt& g) { return g.ground_speed_mm_s; }},
      {"HeadMot", [](const GnssPvt& g) { return g.heading_motion_1e5_deg; }},
      {"SAcc", [](const GnssPvt& g) { return g.speed_accuracy_mm_s; }},
      {"HeadAcc", [](const GnssPvt& g) { return g.heading_accuracy_1e5_deg; }},
      {"HeadVeh", [](const GnssPvt& g) { return g.heading_vehicle_1e5_deg; }},
      {"GDOP", [](const GnssPvt& g) { return g.gdop; }},
      {"PDOP", [](const GnssPvt& g) { return g.pdop; }},
      {"TDOP", [](const GnssPvt& g) { return g.tdop; }},
      {"VDOP", [](const GnssPvt& g) { return g.vdop; }},
      {"HDOP", [](const GnssPvt& g) { return g.hdop; }},
      {"NDOP", [](const GnssPvt& g) { return g.ndop; }},
      {"EDOP", [](const GnssPvt& g) { return g.edop; }},
  };
  return fields;
}

// The client golden names u-blox fix types; these are the ones it uses.
std::int64_t integer_text(const std::string& key, const std::string& text) {
  if (key == "FixType" && text == "3DFix") return 3;
  std::size_t used = 0;
  const std::int64_t v = std::stoll(text, &used);
  if (used != text.size()) ADD_FAILURE() << key << ": not an integer: " << text;
  return v;
}

void expect_section(const GoldenSection& g, const MtData2Packet& packet, const MtData2& m, bool with_format,
                    const std::string& where) {
  SCOPED_TRACE(where + " " + g.header);
  EXPECT_TRUE(same_text_ignoring_case(g.header, header_of(packet.xdi, with_format)))
      << "ours: " << header_of(packet.xdi, with_format);
  const auto info = xdi::info(packet.xdi);
  ASSERT_TRUE(info);
  const auto bare = [&g]() -> std::string {
    EXPECT_EQ(g.entries.size(), 1u);
    EXPECT_EQ(g.entries.empty() ? "?" : g.entries[0].first, "");
    return g.entries.empty() ? "" : g.entries[0].second;
  };
  switch (info->type) {
    case xdi::kPacketCounter: EXPECT_EQ(std::stoll(bare()), m.packet_counter.value_or(-1)); return;
    case xdi::kSampleTimeFine: EXPECT_EQ(std::stoll(bare()), m.sample_time_fine.value_or(0) + 0LL); return;
    case xdi::kSampleTimeCoarse: EXPECT_EQ(std::stoll(bare()), m.sample_time_coarse.value_or(0) + 0LL); return;
    case xdi::kBaroPressure: EXPECT_EQ(std::stoll(bare()), m.baro_pressure_pa.value_or(0) + 0LL); return;
    case xdi::kStatusWord: EXPECT_EQ(bare(), binary(m.status_word.value_or(0), 32)); return;
    case xdi::kStatusByte: EXPECT_EQ(bare(), binary(m.status_byte.value_or(0), 8)); return;
    case xdi::kUtcTime: {
      ASSERT_TRUE(m.utc_time);
      const UtcTime t = parse_utc(bare());
      EXPECT_EQ(t.year, m.utc_time->year);
      EXPECT_EQ(t.month, m.utc_time->month);
      EXPECT_EQ(t.day, m.utc_time->day);
      EXPECT_EQ(t.hour, m.utc_time->hour);
      EXPECT_EQ(t.minute, m.utc_time->minute);
      EXPECT_EQ(t.second, m.utc_time->second);
      EXPECT_EQ(t.nanosecond, m.utc_time->nanosecond);
      return;
    }
    case xdi::kGnssPvtData: {
      ASSERT_TRUE(m.gnss_pvt);
      EXPECT_EQ(g.entries.size(), pvt_fields().size());
      for (const auto& [key, text] : g.entries) {
        const auto field = pvt_fields().find(key);
        ASSERT_NE(field, pvt_fields().end()) << key;
        EXPECT_EQ(integer_text(key, text), field->second(*m.gnss_pvt)) << key;
      }
      return;
    }
    case xdi::kGnssSatInfo: {
      ASSERT_TRUE(m.gnss_sat_info);
      const GnssSatInfo& s = *m.gnss_sat_info;
      const std::map<std::string, std::int64_t> ours{{"ITOW", s.itow_ms},
                                                     {"NumSVS", s.satellites},
                                                     {"Res1", s.reserved[0]},
                                                     {"Res2", s.reserved[1]},
                                                     {"Res3", s.reserved[2]}};
      EXPECT_EQ(g.entries.size(), ours.size());
      for (const auto& [key, text] : g.entries) {
        ASSERT_TRUE(ours.count(key)) << key;
        EXPECT_EQ(integer_text(key, text), ours.at(key)) << key;
      }
      EXPECT_EQ(packet.data.size(), 8u + 4u * s.satellites);
      return;
    }
    default: break;
  }
  ASSERT_EQ(info->layout, xdi::Layout::Reals);
  const std::vector<double> ours = reals_of(m, info->type);
  const std::vector<std::string> keys = keys_for(info->count);
  ASSERT_EQ(ours.size(), info->count);
  ASSERT_EQ(g.entries.size(), ours.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(g.entries[i].first, keys[i]);
    EXPECT_EQ(std::strtod(g.entries[i].second.c_str(), nullptr), ours[i]) << keys[i] << " = " << g.entries[i].second;
  }
}

std::vector<test_util::OwnedFrame> frames_of(int n, std::size_t chunk_bytes = 0) {
  const auto bytes = test_util::read_file(test::fixture_path(fixture_dir(n) + "output.bin"));
  FrameReader reader;
  auto frames = test_util::read_frames(reader, bytes, chunk_bytes);
  EXPECT_EQ(reader.stats().bytes_discarded, 0u);
  EXPECT_EQ(reader.stats().bad_frames(), 0u);
  EXPECT_EQ(reader.buffered_bytes(), 0u);
  return frames;
}

void expect_messages_match(int n, const std::vector<GoldenMessage>& golden, bool with_format) {
  const auto frames = frames_of(n);
  ASSERT_EQ(frames.size(), golden.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::string where = fixture_dir(n) + " message " + std::to_string(i);
    ASSERT_EQ(frames[i].mid, mid::kMtData2) << where;
    MtData2 m;
    MtData2DecodeStats stats;
    ASSERT_TRUE(decode_mtdata2(frames[i].payload, m, stats)) << where;
    EXPECT_EQ(stats.unknown_packets + stats.size_mismatches, 0u) << where;
    MtData2PacketReader packets(frames[i].payload);
    std::size_t section = 0;
    while (const auto packet = packets.next()) {
      ASSERT_LT(section, golden[i].size()) << where;
      expect_section(golden[i][section++], *packet, m, with_format, where);
    }
    EXPECT_EQ(section, golden[i].size()) << where;
  }
}

class EinrideGolden : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override {
    const std::string dir = fixture_dir(GetParam());
    for (const char* file : {"output.bin", "messages.golden", "output.golden", "output.client.golden",
                             "outputconfig.bin", "outputconfig.golden"}) {
      if (!std::filesystem::exists(test::fixture_path(dir + file)))
        GTEST_SKIP() << "fixture " << dir << file << " not found under " TUMBLE_FIXTURES_DIR;
    }
  }
};

TEST_P(EinrideGolden, FramesAreTheGoldenMessages) {
  const auto golden = test_util::parse_messages_golden(test::fixture_path(fixture_dir(GetParam()) + "messages.golden"));
  const auto frames = frames_of(GetParam(), 17);  // serial-sized pieces
  ASSERT_EQ(frames.size(), 100u);
  ASSERT_EQ(golden.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i)
    EXPECT_EQ(encode_xbus_frame(frames[i].mid, frames[i].payload, frames[i].bus_id), golden[i]) << "message " << i;
}

TEST_P(EinrideGolden, EveryValueEqualsOutputGolden) {
  const auto golden = test_util::parse_output_golden(test::fixture_path(fixture_dir(GetParam()) + "output.golden"));
  expect_messages_match(GetParam(), golden, true);
}

TEST_P(EinrideGolden, EveryValueEqualsClientGolden) {
  const auto golden =
      test_util::parse_client_golden(test::fixture_path(fixture_dir(GetParam()) + "output.client.golden"));
  expect_messages_match(GetParam(), golden, false);
}

// outputconfig.golden: "Name(coordinates,format):" then "Max" or "N Hz".
TEST_P(EinrideGolden, OutputConfigurationEqualsGolden) {
  const std::string dir = fixture_dir(GetParam());
  const auto settings = parse_output_configuration(test_util::read_file(test::fixture_path(dir + "outputconfig.bin")));
  const auto golden = test_util::parse_output_golden(test::fixture_path(dir + "outputconfig.golden"));
  ASSERT_EQ(golden.size(), 1u);
  ASSERT_EQ(golden[0].size(), settings.size());
  for (std::size_t i = 0; i < settings.size(); ++i) {
    const GoldenSection& g = golden[0][i];
    SCOPED_TRACE(g.header);
    EXPECT_TRUE(same_text_ignoring_case(g.header, header_of(settings[i].xdi, true)))
        << "ours: " << header_of(settings[i].xdi, true);
    ASSERT_EQ(g.entries.size(), 1u);
    const std::string rate = settings[i].rate_hz == kRateEveryMessage ? "Max" : std::to_string(settings[i].rate_hz) + " Hz";
    EXPECT_EQ(g.entries[0].second, rate);
  }
}

// The IMU messages become samples; GNSS-only messages do not. In 2..4 the
// device sent StatusByte (no clip flags) and the samples say not saturated.
TEST_P(EinrideGolden, ImuSamplesComeFromImuMessagesOnly) {
  const auto golden = test_util::parse_output_golden(test::fixture_path(fixture_dir(GetParam()) + "output.golden"));
  std::size_t imu_messages = 0, non_imu = 0;
  for (const GoldenMessage& message : golden) {
    bool acc = false, gyro = false, dv = false, dq = false;
    for (const GoldenSection& s : message) {
      const std::string name = s.header.substr(0, s.header.find('('));
      acc |= name == "Acceleration";
      gyro |= name == "RateOfTurn";
      dv |= name == "DeltaV";
      dq |= name == "DeltaQ";
    }
    ((acc && gyro) || (dv && dq) ? imu_messages : non_imu)++;
  }
  const auto bytes = test_util::read_file(test::fixture_path(fixture_dir(GetParam()) + "output.bin"));
  MtiStreamOptions options;
  options.epoch_s = 1'547'992'000.0;
  MtiStream stream(options);
  std::vector<ImuSample> samples;
  stream.feed_untimed(bytes, samples);
  EXPECT_EQ(samples.size(), imu_messages);
  EXPECT_EQ(stream.stats().imu_samples, imu_messages);
  EXPECT_EQ(stream.stats().non_imu_messages, non_imu);
  EXPECT_EQ(stream.stats().packet_counter_gaps, 0u);
  EXPECT_EQ(stream.stats().sample_time_gaps, 0u);
  EXPECT_EQ(stream.stats().clipped_samples, 0u);
  // 10 ms apart, to the resolution of a double near 1.5e9 s (2.4e-7 s).
  for (std::size_t i = 1; i < samples.size(); ++i) EXPECT_NEAR(samples[i].t_s - samples[i - 1].t_s, 0.01, 5e-7);
}

// DeltaV and DeltaQ (increments over the 10 ms period) turned into rates
// agree with the device's own Acceleration and RateOfTurn, to within the
// resolution of the increments' format (in Fp12.20 one step of DeltaQ is
// 2 * 2^-20 / 0.01 s = 1.9e-4 rad/s) and a small intrinsic difference.
// Fixtures 1..4 carry DeltaV and DeltaQ next to the rates; 5 has neither.
class EinrideDeltas : public EinrideGolden {};

TEST_P(EinrideDeltas, DeltaOutputsAgreeWithRates) {
  constexpr double kPeriod_s = 0.01;
  const double step = GetParam() == 2 ? 1.0 / 1048576.0 : 0.0;
  const double accel_tol_m_s2 = 1e-3 + 2 * step / kPeriod_s;
  const double gyro_tol_rad_s = 2e-4 + 2 * (2 * step / kPeriod_s);
  std::size_t compared = 0;
  for (const auto& frame : frames_of(GetParam())) {
    MtData2 m;
    MtData2DecodeStats stats;
    ASSERT_TRUE(decode_mtdata2(frame.payload, m, stats));
    if (!m.acceleration_m_s2 || !m.rate_of_turn_rad_s || !m.delta_v_m_s || !m.delta_q) continue;
    MtData2 deltas_only = m;
    deltas_only.acceleration_m_s2.reset();
    deltas_only.rate_of_turn_rad_s.reset();
    ImuSample s;
    ASSERT_TRUE(fill_imu_sample(deltas_only, kPeriod_s, s));
    for (int i = 0; i < 3; ++i) {
      const double accel = (*m.acceleration_m_s2)[i], gyro = (*m.rate_of_turn_rad_s)[i];
      EXPECT_NEAR(s.accel_m_s2[i], accel, accel_tol_m_s2 + 0.01 * std::abs(accel));
      EXPECT_NEAR(s.gyro_rad_s[i], gyro, gyro_tol_rad_s + 0.02 * std::abs(gyro));
    }
    ++compared;
  }
  EXPECT_EQ(compared, 96u);
}

std::string fixture_name(const ::testing::TestParamInfo<int>& info) {
  const std::array<const char*, 6> names{"", "Float32", "Fp1220", "Fp1632", "Float64", "ManyOutputs"};
  return names[static_cast<std::size_t>(info.param)];
}

INSTANTIATE_TEST_SUITE_P(Fixtures, EinrideGolden, ::testing::Values(1, 2, 3, 4, 5), fixture_name);
INSTANTIATE_TEST_SUITE_P(Fixtures, EinrideDeltas, ::testing::Values(1, 2, 3, 4), fixture_name);

}  // namespace
}  // namespace tumble::mti
