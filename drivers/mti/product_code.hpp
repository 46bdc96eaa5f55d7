// Sensor ranges from the MTi product code, e.g. "MTi-30-2A8G4": A8 = +-20 g
// accelerometer, G4 = +-450 deg/s gyroscope (G0 = 1000 deg/s).
#pragma once

#include <optional>
#include <string_view>

namespace tumble::mti {

struct SensorRanges {
  std::optional<double> gyro_rad_s;   // nullopt: code not recognised
  std::optional<double> accel_m_s2;
};

SensorRanges ranges_from_product_code(std::string_view product_code);

}  // namespace tumble::mti
