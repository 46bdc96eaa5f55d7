#include "drivers/rs16/utc_time.hpp"

#include <stdexcept>
#include <string>

namespace tumble::rs16 {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;
constexpr std::int64_t kSPerDay = 86'400;

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's
// days_from_civil): the same arithmetic timegm does, with no time zone.
constexpr std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

struct CivilDate {
  std::int64_t year;
  unsigned month, day;
};

constexpr CivilDate civil_from_days(std::int64_t z) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  const unsigned d = doy - (153 * mp + 2) / 5 + 1;
  const unsigned m = mp < 10 ? mp + 3 : mp - 9;
  return {static_cast<std::int64_t>(yoe) + era * 400 + (m <= 2 ? 1 : 0), m, d};
}

constexpr bool is_leap(std::int64_t y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

constexpr unsigned days_in_month(std::int64_t y, unsigned m) {
  constexpr unsigned kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && is_leap(y) ? 29 : kDays[m - 1];
}

}  // namespace

std::optional<std::int64_t> decode_utc_time_ns(std::span<const std::uint8_t, 10> b) {
  const std::int64_t year = 2000 + b[0];
  const unsigned month = b[1], day = b[2], hour = b[3], minute = b[4], second = b[5];
  const unsigned ms = (unsigned{b[6]} << 8) | b[7];
  const unsigned us = (unsigned{b[8]} << 8) | b[9];
  if (month < 1 || month > 12 || day < 1 || day > days_in_month(year, month)) return std::nullopt;
  // Second 60 is a leap second; timegm folds it into the next minute, so do we.
  if (hour > 23 || minute > 59 || second > 60 || ms > 999 || us > 999) return std::nullopt;
  const std::int64_t s = days_from_civil(year, month, day) * kSPerDay + hour * 3600 + minute * 60 + second;
  return s * kNsPerS + static_cast<std::int64_t>(ms) * 1'000'000 + static_cast<std::int64_t>(us) * 1'000;
}

void encode_utc_time_ns(std::int64_t t_ns, std::span<std::uint8_t, 10> b) {
  std::int64_t days = t_ns / (kSPerDay * kNsPerS);
  std::int64_t ns_of_day = t_ns % (kSPerDay * kNsPerS);
  if (ns_of_day < 0) {
    ns_of_day += kSPerDay * kNsPerS;
    --days;
  }
  const CivilDate date = civil_from_days(days);
  if (date.year < 2000 || date.year > 2255)
    throw std::out_of_range("RS-16 UTC time: year " + std::to_string(date.year) + " is outside 2000..2255");
  const std::int64_t s_of_day = ns_of_day / kNsPerS;
  const std::int64_t us_of_s = (ns_of_day % kNsPerS) / 1000;
  b[0] = static_cast<std::uint8_t>(date.year - 2000);
  b[1] = static_cast<std::uint8_t>(date.month);
  b[2] = static_cast<std::uint8_t>(date.day);
  b[3] = static_cast<std::uint8_t>(s_of_day / 3600);
  b[4] = static_cast<std::uint8_t>((s_of_day / 60) % 60);
  b[5] = static_cast<std::uint8_t>(s_of_day % 60);
  const auto ms = static_cast<std::uint16_t>(us_of_s / 1000);
  const auto us = static_cast<std::uint16_t>(us_of_s % 1000);
  b[6] = static_cast<std::uint8_t>(ms >> 8);
  b[7] = static_cast<std::uint8_t>(ms & 0xFF);
  b[8] = static_cast<std::uint8_t>(us >> 8);
  b[9] = static_cast<std::uint8_t>(us & 0xFF);
}

}  // namespace tumble::rs16
