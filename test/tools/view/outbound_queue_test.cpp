#include "tools/view/outbound_queue.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace tumble::view {
namespace {

FramePtr frame(FrameKind kind, bool newest_only, std::string bytes) {
  return std::make_shared<const Frame>(Frame{kind, false, newest_only, std::move(bytes)});
}

TEST(OutboundQueue, ANewerFrameOfANewestOnlyKindReplacesTheWaitingOneInItsPlace) {
  OutboundQueue q(8);
  q.push(frame(FrameKind::kStatus, true, "status 1"));
  q.push(frame(FrameKind::kPose, false, "pose 1"));
  q.push(frame(FrameKind::kStatus, true, "status 2"));
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q.pop()->bytes, "status 2");
  EXPECT_EQ(q.pop()->bytes, "pose 1");
  EXPECT_EQ(q.pop(), nullptr);
  EXPECT_EQ(q.dropped(), 1u);
}

TEST(OutboundQueue, QueuedKindsKeepTheirOrderAndPastTheCapacityTheOldestGo) {
  OutboundQueue q(3);
  for (int i = 0; i < 1000; ++i) q.push(frame(FrameKind::kPose, false, std::to_string(i)));
  ASSERT_EQ(q.size(), 3u);
  EXPECT_EQ(q.dropped(), 997u);
  EXPECT_EQ(q.pop()->bytes, "997");
  EXPECT_EQ(q.pop()->bytes, "998");
  EXPECT_EQ(q.pop()->bytes, "999");
}

TEST(OutboundQueue, StaysBoundedWhateverTheMixOfKinds) {
  OutboundQueue q(16);
  for (int i = 0; i < 10000; ++i) {
    q.push(frame(FrameKind::kScan, true, "scan"));
    q.push(frame(FrameKind::kPose, false, "pose"));
    q.push(frame(FrameKind::kStatus, true, "status"));
  }
  EXPECT_LE(q.size(), 16u);
}

}  // namespace
}  // namespace tumble::view
