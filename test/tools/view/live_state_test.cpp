#include "tools/view/live_state.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "tools/view/frames.hpp"

namespace tumble::view {
namespace {

FramePtr pose(std::int64_t index) {
  tumble::registration_t r{};
  r.scan_index = index;
  return std::make_shared<const Frame>(pose_frame(r));
}

TEST(LiveState, NotifiesOnceUntilThePendingFramesAreTaken) {
  LiveState state;
  int notified = 0;
  state.on_pending([&] { ++notified; });
  const double p[3] = {1, 2, 3};
  for (int i = 0; i < 5; ++i) state.add_pose(pose(i), i, p);
  EXPECT_EQ(notified, 1);
  EXPECT_EQ(state.take_pending().size(), 5u);
  state.add_pose(pose(5), 5, p);
  EXPECT_EQ(notified, 2);
  EXPECT_EQ(state.messages(), 6u);
}

TEST(LiveState, AJoiningBrowserGetsTheNewestTrajectoryBoundedAndTheNewestStatus) {
  LiveState state(/*max_history_poses=*/100, /*pending_capacity=*/8);
  for (int i = 0; i < 1000; ++i) {
    const double p[3] = {static_cast<double>(i), 0, 0};
    state.add_pose(pose(i), i, p);
  }
  tumble::status_t s{};
  s.state_name = "TRACKING";
  state.add(std::make_shared<const Frame>(status_frame(s)));
  EXPECT_LE(state.take_pending().size(), 8u);
  const auto frames = state.joining_frames();
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0]->kind, FrameKind::kHistory);
  EXPECT_EQ(frames[0]->bytes.find("[899,0,0,"), std::string::npos);
  EXPECT_NE(frames[0]->bytes.find("[900,0,0,"), std::string::npos);
  EXPECT_EQ(frames[1]->kind, FrameKind::kStatus);
}

TEST(LiveState, AScanIndexGoingBackStartsANewTrajectory) {
  LiveState state;
  const double p[3] = {7, 0, 0};
  state.add_pose(pose(50), 50, p);
  const double q[3] = {1, 0, 0};
  state.add_pose(pose(0), 0, q);
  EXPECT_NE(state.joining_frames()[0]->bytes.find(R"("p":[1,0,0]})"), std::string::npos);
}

TEST(LiveState, NoMessageYetIsNotAnAge) {
  LiveState state;
  EXPECT_FALSE(state.since_last_s(LiveState::Clock::now()));
}

}  // namespace
}  // namespace tumble::view
