// The MTData2 data identifiers (XDIs) this driver knows: name, payload layout
// and expected size. An XDI = group and type (high 12 bits) | coordinate
// system (bits 3-2) | number format (bits 1-0).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "drivers/mti/number_format.hpp"

namespace tumble::mti::xdi {

inline constexpr std::uint16_t kTypeMask = 0xFFF0;
inline constexpr std::uint16_t kCoordinateMask = 0x000C;

inline constexpr std::uint16_t kTemperature = 0x0810;
inline constexpr std::uint16_t kUtcTime = 0x1010;
inline constexpr std::uint16_t kPacketCounter = 0x1020;
inline constexpr std::uint16_t kSampleTimeFine = 0x1060;
inline constexpr std::uint16_t kSampleTimeCoarse = 0x1070;
inline constexpr std::uint16_t kQuaternion = 0x2010;
inline constexpr std::uint16_t kRotationMatrix = 0x2020;
inline constexpr std::uint16_t kEulerAngles = 0x2030;
inline constexpr std::uint16_t kBaroPressure = 0x3010;
inline constexpr std::uint16_t kDeltaV = 0x4010;
inline constexpr std::uint16_t kAcceleration = 0x4020;
inline constexpr std::uint16_t kFreeAcceleration = 0x4030;
inline constexpr std::uint16_t kAltitudeEllipsoid = 0x5020;
inline constexpr std::uint16_t kPositionEcef = 0x5030;
inline constexpr std::uint16_t kLatLon = 0x5040;
inline constexpr std::uint16_t kGnssPvtData = 0x7010;
inline constexpr std::uint16_t kGnssSatInfo = 0x7020;
inline constexpr std::uint16_t kRateOfTurn = 0x8020;
inline constexpr std::uint16_t kDeltaQ = 0x8030;
inline constexpr std::uint16_t kMagneticField = 0xC020;
inline constexpr std::uint16_t kVelocityXyz = 0xD010;
inline constexpr std::uint16_t kStatusByte = 0xE010;
inline constexpr std::uint16_t kStatusWord = 0xE020;

// How a payload is laid out.
enum class Layout : std::uint8_t {
  Reals,        // `count` values in the XDI's number format
  U8,
  U16,
  U32,          // also BaroPressure, whose format bits do not change its size
  UtcTime,      // 12 bytes
  GnssPvt,      // 94 bytes
  GnssSatInfo,  // 8 bytes + 4 per satellite
};

enum class CoordinateSystem : std::uint8_t { EastNorthUp = 0, NorthEastDown = 1, NorthWestUp = 2 };

struct Info {
  std::uint16_t type = 0;  // XDI with coordinate and format bits cleared
  std::string_view name;   // Xsens' name of the output
  Layout layout = Layout::Reals;
  std::uint8_t count = 0;  // values, for Layout::Reals
  bool has_coordinate_system = false;  // orientation and velocity outputs
};

inline constexpr std::size_t kGnssPvtBytes = 94;
inline constexpr std::size_t kGnssSatInfoHeaderBytes = 8;
inline constexpr std::size_t kGnssSatInfoSatelliteBytes = 4;
inline constexpr std::size_t kUtcTimeBytes = 12;

// nullptr / nullopt for an XDI this driver does not decode.
const Info* find(std::uint16_t xdi);
std::optional<Info> info(std::uint16_t xdi);
// The payload size the XDI must have; nullopt when unknown or variable (GnssSatInfo).
std::optional<std::size_t> expected_size(std::uint16_t xdi);
// Whether a packet of this size is well formed for this XDI (false when unknown).
bool size_fits(std::uint16_t xdi, std::size_t size);
bool size_fits(const Info& info, std::uint16_t xdi, std::size_t size);

inline CoordinateSystem coordinate_system_of(std::uint16_t xdi) {
  return static_cast<CoordinateSystem>((xdi & kCoordinateMask) >> 2);
}
std::string_view coordinate_system_name(CoordinateSystem c);

}  // namespace tumble::mti::xdi
