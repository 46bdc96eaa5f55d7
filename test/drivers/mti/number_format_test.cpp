#include "drivers/mti/number_format.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;

double roundtrip(double v, NumberFormat f) {
  Bytes b;
  append_real(b, v, f);
  EXPECT_EQ(b.size(), number_format_bytes(f));
  return read_real(b.data(), f);
}

TEST(NumberFormat, SizesAndNames) {
  EXPECT_EQ(number_format_bytes(NumberFormat::Float32), 4u);
  EXPECT_EQ(number_format_bytes(NumberFormat::Fp1220), 4u);
  EXPECT_EQ(number_format_bytes(NumberFormat::Fp1632), 6u);
  EXPECT_EQ(number_format_bytes(NumberFormat::Float64), 8u);
  EXPECT_EQ(number_format_of(0x4022), NumberFormat::Fp1632);
  EXPECT_EQ(number_format_name(NumberFormat::Fp1220), "Fp1220");
}

// Hand-made bit patterns: the byte order of each format is the point.
TEST(NumberFormat, DecodesKnownBitPatterns) {
  const Bytes f32{0x3F, 0xC0, 0x00, 0x00};
  EXPECT_EQ(read_real(f32.data(), NumberFormat::Float32), 1.5);
  const Bytes fp1220{0xFF, 0xF8, 0x00, 0x00};  // -0.5 * 2^20
  EXPECT_EQ(read_real(fp1220.data(), NumberFormat::Fp1220), -0.5);
  // Fraction u32 first, then the signed integer part: -1 + 0.25 = -0.75.
  const Bytes fp1632{0x40, 0x00, 0x00, 0x00, 0xFF, 0xFF};
  EXPECT_EQ(read_real(fp1632.data(), NumberFormat::Fp1632), -0.75);
  const Bytes fp1632_big{0x80, 0x00, 0x00, 0x00, 0x01, 0x00};  // 256.5
  EXPECT_EQ(read_real(fp1632_big.data(), NumberFormat::Fp1632), 256.5);
  const Bytes f64{0xC0, 0x24, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
  EXPECT_EQ(read_real(f64.data(), NumberFormat::Float64), -10.0);
}

TEST(NumberFormat, RoundTripsWithinEachFormatsResolution) {
  for (const double v : {0.0, 1e-7, -3.14159265358979, 9.80665, -199.9, 1234.56789}) {
    EXPECT_NEAR(roundtrip(v, NumberFormat::Float32), v, std::abs(v) * 6e-8);
    EXPECT_NEAR(roundtrip(v, NumberFormat::Fp1220), v, 0.5 / 1048576.0);
    EXPECT_NEAR(roundtrip(v, NumberFormat::Fp1632), v, 0.5 / 4294967296.0);
    EXPECT_EQ(roundtrip(v, NumberFormat::Float64), v);
  }
}

TEST(NumberFormat, FixedPointSaturatesAtItsRange) {
  EXPECT_NEAR(roundtrip(5000.0, NumberFormat::Fp1220), 2048.0, 1e-6);
  EXPECT_EQ(roundtrip(-5000.0, NumberFormat::Fp1220), -2048.0);
  EXPECT_NEAR(roundtrip(1e6, NumberFormat::Fp1632), 32768.0, 1e-9);
  EXPECT_EQ(roundtrip(-1e6, NumberFormat::Fp1632), -32768.0);
  EXPECT_EQ(roundtrip(1e300, NumberFormat::Float32), static_cast<double>(std::numeric_limits<float>::max()));
  EXPECT_EQ(roundtrip(std::nan(""), NumberFormat::Fp1220), 0.0);
}

}  // namespace
}  // namespace tumble::mti
