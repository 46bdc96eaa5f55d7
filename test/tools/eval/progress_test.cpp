#include "tools/eval/progress.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace tumble::eval {
namespace {

TEST(Progress, FormatsDurations) {
  EXPECT_EQ(format_duration(42.4), "42 s");
  EXPECT_EQ(format_duration(185.0), "3 min 05 s");
  EXPECT_EQ(format_duration(3720.0), "1 h 02 min");
  EXPECT_EQ(format_duration(-1.0), "0 s");
}

TEST(Progress, CountsJobsAndEndsWithDone) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  Progress progress(3, 30.0, out);
  progress.job_finished(10.0, false, "cage-00 NM-deskew: failed (run folder missing)");
  progress.job_finished(10.0, true, "cage-01 NM-deskew: ok");
  progress.job_finished(10.0, true, "cage-02 NM-deskew: ok");
  std::rewind(out);
  char buffer[512] = {};
  const std::size_t read = std::fread(buffer, 1, sizeof buffer - 1, out);
  std::fclose(out);
  const std::string text(buffer, read);
  EXPECT_NE(text.find("eval: [1/3] cage-00 NM-deskew: failed (run folder missing) | "), std::string::npos) << text;
  EXPECT_NE(text.find("elapsed, ETA unknown\n"), std::string::npos) << text;
  EXPECT_NE(text.find("eval: [2/3] cage-01 NM-deskew: ok | "), std::string::npos) << text;
  EXPECT_NE(text.find("elapsed, ETA "), std::string::npos) << text;
  EXPECT_NE(text.find("eval: [3/3] cage-02 NM-deskew: ok | "), std::string::npos) << text;
  EXPECT_NE(text.find("elapsed, done\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace tumble::eval
