#include "drivers/mti/xdi.hpp"

#include <array>

namespace tumble::mti::xdi {
namespace {

constexpr std::array<Info, 23> kTable{{
    {kTemperature, "Temperature", Layout::Reals, 1, false},
    {kUtcTime, "UtcTime", Layout::UtcTime, 0, false},
    {kPacketCounter, "PacketCounter", Layout::U16, 0, false},
    {kSampleTimeFine, "SampleTimeFine", Layout::U32, 0, false},
    {kSampleTimeCoarse, "SampleTimeCoarse", Layout::U32, 0, false},
    {kQuaternion, "Quaternion", Layout::Reals, 4, true},
    {kRotationMatrix, "RotationMatrix", Layout::Reals, 9, true},
    {kEulerAngles, "EulerAngles", Layout::Reals, 3, true},
    {kBaroPressure, "BaroPressure", Layout::U32, 0, false},
    {kDeltaV, "DeltaV", Layout::Reals, 3, false},
    {kAcceleration, "Acceleration", Layout::Reals, 3, false},
    {kFreeAcceleration, "FreeAcceleration", Layout::Reals, 3, false},
    {kAltitudeEllipsoid, "AltitudeEllipsoid", Layout::Reals, 1, false},
    {kPositionEcef, "PositionEcef", Layout::Reals, 3, false},
    {kLatLon, "LatLon", Layout::Reals, 2, false},
    {kGnssPvtData, "GnssPvtData", Layout::GnssPvt, 0, false},
    {kGnssSatInfo, "GnssSatInfo", Layout::GnssSatInfo, 0, false},
    {kRateOfTurn, "RateOfTurn", Layout::Reals, 3, false},
    {kDeltaQ, "DeltaQ", Layout::Reals, 4, false},
    {kMagneticField, "MagneticField", Layout::Reals, 3, false},
    {kVelocityXyz, "VelocityXYZ", Layout::Reals, 3, true},
    {kStatusByte, "StatusByte", Layout::U8, 0, false},
    {kStatusWord, "StatusWord", Layout::U32, 0, false},
}};

// Table position by XDI type (the high 12 bits), -1 for unknown: one lookup
// per packet on the decoding path.
constexpr std::array<std::int8_t, 4096> make_index() {
  std::array<std::int8_t, 4096> index{};
  index.fill(-1);
  for (std::size_t i = 0; i < kTable.size(); ++i) index[kTable[i].type >> 4] = static_cast<std::int8_t>(i);
  return index;
}
constexpr std::array<std::int8_t, 4096> kIndex = make_index();

std::optional<std::size_t> expected_size(const Info& i, std::uint16_t xdi) {
  switch (i.layout) {
    case Layout::Reals: return i.count * number_format_bytes(number_format_of(xdi));
    case Layout::U8: return 1;
    case Layout::U16: return 2;
    case Layout::U32: return 4;
    case Layout::UtcTime: return kUtcTimeBytes;
    case Layout::GnssPvt: return kGnssPvtBytes;
    case Layout::GnssSatInfo: return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

const Info* find(std::uint16_t xdi) {
  const std::int8_t i = kIndex[xdi >> 4];
  return i < 0 ? nullptr : &kTable[static_cast<std::size_t>(i)];
}

std::optional<Info> info(std::uint16_t xdi) {
  const Info* i = find(xdi);
  return i ? std::optional<Info>(*i) : std::nullopt;
}

std::optional<std::size_t> expected_size(std::uint16_t xdi) {
  const Info* i = find(xdi);
  return i ? expected_size(*i, xdi) : std::nullopt;
}

bool size_fits(const Info& i, std::uint16_t xdi, std::size_t size) {
  if (const auto expected = expected_size(i, xdi)) return size == *expected;
  return i.layout == Layout::GnssSatInfo && size >= kGnssSatInfoHeaderBytes &&
         (size - kGnssSatInfoHeaderBytes) % kGnssSatInfoSatelliteBytes == 0;
}

bool size_fits(std::uint16_t xdi, std::size_t size) {
  const Info* i = find(xdi);
  return i != nullptr && size_fits(*i, xdi, size);
}

std::string_view coordinate_system_name(CoordinateSystem c) {
  switch (c) {
    case CoordinateSystem::EastNorthUp: return "EastNorthUp";
    case CoordinateSystem::NorthEastDown: return "NorthEastDown";
    case CoordinateSystem::NorthWestUp: return "NorthWestUp";
  }
  return "reserved";
}

}  // namespace tumble::mti::xdi
