#include "drivers/rs16/utc_time.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <ctime>
#include <string>

namespace tumble::rs16 {
namespace {

std::array<std::uint8_t, 10> field(int y, int mo, int d, int h, int mi, int s, int ms, int us) {
  return {static_cast<std::uint8_t>(y), static_cast<std::uint8_t>(mo), static_cast<std::uint8_t>(d),
          static_cast<std::uint8_t>(h), static_cast<std::uint8_t>(mi), static_cast<std::uint8_t>(s),
          static_cast<std::uint8_t>(ms >> 8), static_cast<std::uint8_t>(ms & 0xFF),
          static_cast<std::uint8_t>(us >> 8), static_cast<std::uint8_t>(us & 0xFF)};
}

// Restores the process time zone when a test changed it.
class TimeZone {
 public:
  explicit TimeZone(const char* tz) {
    if (const char* old = std::getenv("TZ")) old_ = old;
    setenv("TZ", tz, 1);
    tzset();
  }
  ~TimeZone() {
    if (old_.empty())
      unsetenv("TZ");
    else
      setenv("TZ", old_.c_str(), 1);
    tzset();
  }

 private:
  std::string old_;
};

TEST(Rs16UtcTime, DecodesAsUtcWhateverTheHostTimeZone) {
  const TimeZone tz("Asia/Kathmandu");  // +05:45: any local-time decode would be visibly off
  const auto t = decode_utc_time_ns(field(24, 1, 1, 0, 0, 0, 1, 332));
  ASSERT_TRUE(t);
  EXPECT_EQ(*t, 1'704'067'200'001'332'000);
}

TEST(Rs16UtcTime, AgreesWithTimegmOverLeapYearsAndMonthEnds) {
  for (const auto& [y, mo, d] : {std::array{0, 1, 1}, std::array{0, 2, 29}, std::array{23, 12, 31},
                                  std::array{24, 2, 29}, std::array{38, 1, 19}, std::array{99, 3, 1}}) {
    std::tm tm{};
    tm.tm_year = 100 + y;
    tm.tm_mon = mo - 1;
    tm.tm_mday = d;
    tm.tm_hour = 13;
    tm.tm_min = 7;
    tm.tm_sec = 59;
    const std::int64_t expected_s = timegm(&tm);
    const auto t = decode_utc_time_ns(field(y, mo, d, 13, 7, 59, 999, 999));
    ASSERT_TRUE(t) << y << "-" << mo << "-" << d;
    EXPECT_EQ(*t, expected_s * 1'000'000'000 + 999'999'000) << y << "-" << mo << "-" << d;
  }
}

TEST(Rs16UtcTime, RejectsFieldsOutOfRange) {
  EXPECT_FALSE(decode_utc_time_ns(field(24, 0, 1, 0, 0, 0, 0, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(24, 13, 1, 0, 0, 0, 0, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(23, 2, 29, 0, 0, 0, 0, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(24, 4, 31, 0, 0, 0, 0, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(24, 1, 1, 24, 0, 0, 0, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(24, 1, 1, 0, 60, 0, 0, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(24, 1, 1, 0, 0, 61, 0, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(24, 1, 1, 0, 0, 0, 1000, 0)));
  EXPECT_FALSE(decode_utc_time_ns(field(24, 1, 1, 0, 0, 0, 0, 1000)));
  EXPECT_FALSE(decode_utc_time_ns(field(0, 0, 0, 0, 0, 0, 0, 0)));  // an unset clock
}

TEST(Rs16UtcTime, EncodeThenDecodeKeepsWholeMicroseconds) {
  for (const std::int64_t t : {std::int64_t{946'684'800'000'000'000}, std::int64_t{1'704'067'200'001'332'000},
                               std::int64_t{1'709'251'199'999'999'000}, std::int64_t{4'102'444'799'123'456'000}}) {
    std::array<std::uint8_t, 10> b{};
    encode_utc_time_ns(t + 789, b);  // sub-microsecond part is dropped
    const auto back = decode_utc_time_ns(b);
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, t);
  }
}

TEST(Rs16UtcTime, EncodeRefusesYearsTheFieldCannotHold) {
  std::array<std::uint8_t, 10> b{};
  EXPECT_THROW(encode_utc_time_ns(0, b), std::out_of_range);
  EXPECT_THROW(encode_utc_time_ns(std::int64_t{9'100'000'000} * 1'000'000'000, b), std::out_of_range);
}

}  // namespace
}  // namespace tumble::rs16
