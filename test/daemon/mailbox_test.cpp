#include "daemon/mailbox.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test/daemon/alloc_counter.hpp"

namespace tumble::daemon {
namespace {

TEST(Mailbox, ReaderGetsTheNewestValueOnce) {
  Mailbox<int> box;
  EXPECT_EQ(box.take(), nullptr);
  box.draft() = 1;
  box.publish();
  box.draft() = 2;
  box.publish();
  EXPECT_TRUE(box.has_new());
  const int* value = box.take();
  ASSERT_NE(value, nullptr);
  EXPECT_EQ(*value, 2);
  EXPECT_EQ(box.take(), nullptr);
  EXPECT_EQ(box.published(), 2u);
  EXPECT_EQ(box.replaced(), 1u);
}

TEST(Mailbox, TakenValueStaysValidWhileTheWriterGoesOn) {
  Mailbox<std::string> box;
  box.draft() = "first";
  box.publish();
  const std::string* taken = box.take();
  for (int i = 0; i < 5; ++i) {
    box.draft() = "later " + std::to_string(i);
    box.publish();
  }
  EXPECT_EQ(*taken, "first");
  EXPECT_EQ(*box.take(), "later 4");
}

TEST(Mailbox, ReusedBuffersStopAllocatingOnceGrown) {
  Mailbox<std::vector<float>> box;
  for (int i = 0; i < 6; ++i) {  // every buffer reaches its working size
    box.draft().assign(1000, 1.0f);
    box.publish();
    box.take();
  }
  test::AllocationCounter allocations;
  for (int i = 0; i < 100; ++i) {
    box.draft().assign(1000, static_cast<float>(i));
    box.publish();
    if (i % 2 == 0) box.take();
  }
  EXPECT_EQ(allocations.count(), 0u);
}

}  // namespace
}  // namespace tumble::daemon
