#include "daemon/rate_limited_log.hpp"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>

#include <algorithm>
#include <sstream>
#include <string>

namespace tumble::daemon {
namespace {

class RateLimitedLogTest : public ::testing::Test {
 protected:
  RateLimitedLogTest()
      : logger_(std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::ostream_sink_st>(text_))) {
    logger_->set_pattern("%v");
  }
  int lines() const {
    const std::string t = text_.str();
    return static_cast<int>(std::count(t.begin(), t.end(), '\n'));
  }
  std::ostringstream text_;
  std::shared_ptr<spdlog::logger> logger_;
};

TEST_F(RateLimitedLogTest, AtMostNPerPeriodPerKey) {
  RateLimitedLog log(3, 1.0, logger_);
  for (int i = 0; i < 100; ++i) log.warn("bad packet", 0.001 * i, "bad packet {}", i);
  EXPECT_EQ(lines(), 3);
  for (int i = 0; i < 100; ++i) log.warn("checksum", 0.001 * i, "checksum {}", i);
  EXPECT_EQ(lines(), 6);  // another key has its own budget
}

TEST_F(RateLimitedLogTest, NextPeriodReportsWhatWasSuppressed) {
  RateLimitedLog log(2, 1.0, logger_);
  for (int i = 0; i < 10; ++i) log.warn("k", 0.1 * i, "line {}", i);  // 0.0 .. 0.9: two pass
  log.warn("k", 1.0, "line {}", 10);
  EXPECT_EQ(lines(), 3);
  EXPECT_NE(text_.str().find("line 10 (8 similar suppressed)"), std::string::npos) << text_.str();
}

TEST_F(RateLimitedLogTest, ManyKeysForgetTheLeastRecentlyActive) {
  RateLimitedLog log(1, 10.0, logger_);
  for (std::size_t i = 0; i <= RateLimitedLog::kMaxKeys; ++i) {
    log.warn("key " + std::to_string(i), static_cast<double>(i), "first of key {}", i);
  }
  EXPECT_EQ(lines(), static_cast<int>(RateLimitedLog::kMaxKeys) + 1);
  log.warn("key 32", 40.0, "again");  // still known: suppressed (its period runs until 42)
  EXPECT_EQ(lines(), static_cast<int>(RateLimitedLog::kMaxKeys) + 1);
  std::uint64_t suppressed = 0;
  EXPECT_TRUE(log.admit("key 0", 40.0, suppressed));  // evicted earlier, so a new budget
}

}  // namespace
}  // namespace tumble::daemon
