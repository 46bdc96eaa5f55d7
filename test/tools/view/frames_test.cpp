#include "tools/view/frames.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace tumble::view {
namespace {

float float_at(const std::string& bytes, std::size_t index) {
  float v;
  std::memcpy(&v, bytes.data() + 16 + 4 * index, 4);
  return v;
}

std::uint32_t u32_at(const std::string& bytes, std::size_t offset) {
  std::uint32_t v;
  std::memcpy(&v, bytes.data() + offset, 4);
  return v;
}

TEST(Frames, StatusIsJsonWithTheStateItsReasonEscapedAndNullForWhatWasNotMeasured) {
  tumble::status_t s{};
  s.state = tumble::status_t::STATE_DEGRADED;
  s.state_name = "DEGRADED";
  s.state_reason = "a \"quoted\" reason\nover two lines";
  s.pose_latency_p50_ms = std::numeric_limits<float>::quiet_NaN();
  s.scans_jumped = 7;
  s.num_stages = 1;
  s.stage_name = {"icp"};
  s.stage_median_ms = {1.5f};
  s.stage_max_ms = {std::numeric_limits<float>::infinity()};
  const Frame f = status_frame(s);
  EXPECT_FALSE(f.binary);
  EXPECT_TRUE(f.newest_only);
  EXPECT_NE(f.bytes.find(R"("state":3)"), std::string::npos);
  EXPECT_NE(f.bytes.find(R"("reason":"a \"quoted\" reason\nover two lines")"), std::string::npos);
  EXPECT_NE(f.bytes.find(R"j("pose p50 (ms)":null)j"), std::string::npos);
  EXPECT_NE(f.bytes.find(R"("scans_jumped":7)"), std::string::npos);
  EXPECT_NE(f.bytes.find(R"(["icp",1.5,null])"), std::string::npos);
  EXPECT_EQ(f.bytes.find("nan"), std::string::npos);
  EXPECT_EQ(f.bytes.find("inf"), std::string::npos);
}

TEST(Frames, PosesQueueAndCarryPositionAndOrientation) {
  tumble::registration_t r{};
  r.scan_index = 42;
  r.position_m[0] = 1.25;
  r.orientation[0] = 1;
  r.registered = true;
  const Frame f = pose_frame(r);
  EXPECT_FALSE(f.newest_only);
  EXPECT_NE(f.bytes.find(R"("scan_index":42,"p":[1.25,0,0],"q":[1,0,0,0],"registered":true)"), std::string::npos);
}

TEST(Frames, AScanIsAHeaderThenOneFloatArrayPerField) {
  tumble::scan_t s{};
  s.scan_index = 9;
  s.num_points = 2;
  s.x_m = {1, 2};
  s.y_m = {3, 4};
  s.z_m = {5, 6};
  s.sigma_s_m = {0.01f, 0.02f};
  s.weight = {1.0f, 0.5f};
  s.ring = {0, 15};
  const Frame f = scan_frame(s);
  EXPECT_TRUE(f.binary);
  ASSERT_EQ(f.bytes.size(), 16u + 6 * 2 * 4);
  EXPECT_EQ(f.bytes.substr(0, 4), "SCAN");
  EXPECT_EQ(u32_at(f.bytes, 4), 2u);
  EXPECT_EQ(u32_at(f.bytes, 8), 9u);
  EXPECT_EQ(u32_at(f.bytes, 12), 1u);
  EXPECT_EQ(float_at(f.bytes, 1), 2.0f);   // x[1]
  EXPECT_EQ(float_at(f.bytes, 4), 5.0f);   // z[0]
  EXPECT_EQ(float_at(f.bytes, 9), 0.5f);   // weight[1]
  EXPECT_EQ(float_at(f.bytes, 11), 15.0f); // ring[1]
}

TEST(Frames, AMapLargerThanABrowserDrawsIsStrided) {
  tumble::map_t m{};
  m.num_points = static_cast<std::int32_t>(3 * kMaxMapPoints);
  m.map_points = 2 * m.num_points;
  m.x_m.resize(static_cast<std::size_t>(m.num_points));
  for (std::size_t i = 0; i < m.x_m.size(); ++i) m.x_m[i] = static_cast<float>(i);
  m.y_m = m.x_m;
  m.z_m = m.x_m;
  const Frame f = map_frame(m);
  EXPECT_EQ(f.bytes.substr(0, 4), "MAP_");
  EXPECT_EQ(u32_at(f.bytes, 4), kMaxMapPoints);
  EXPECT_EQ(u32_at(f.bytes, 8), static_cast<std::uint32_t>(m.map_points));
  EXPECT_EQ(u32_at(f.bytes, 12), 3u);
  EXPECT_EQ(float_at(f.bytes, 1), 3.0f);
  EXPECT_EQ(f.bytes.size(), 16u + 3 * kMaxMapPoints * 4);
}

TEST(Frames, TheLinkSaysNullUntilAMessageArrived) {
  LinkReport link{"udpm://239.255.76.67:7667?ttl=0", "TUMBLE_", 0, -1.0, 1};
  EXPECT_NE(link_frame(link).bytes.find(R"("since_last_s":null)"), std::string::npos);
  link.since_last_s = 2.5;
  EXPECT_NE(link_frame(link).bytes.find(R"("since_last_s":2.5)"), std::string::npos);
}

}  // namespace
}  // namespace tumble::view
