// tumbled's logging: no thread waits for stderr, and every line queued is
// written by the end.
#include "daemon/logging.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spdlog/async_logger.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "test/temp_dir.hpp"

namespace tumble::daemon {
namespace {

// Sends stderr to a file while alive.
class StderrToFile {
 public:
  explicit StderrToFile(const std::string& path)
      : saved_(::dup(STDERR_FILENO)), file_(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644)) {
    std::fflush(stderr);
    ::dup2(file_, STDERR_FILENO);
  }
  ~StderrToFile() {
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(file_);
    ::close(saved_);
  }
  StderrToFile(const StderrToFile&) = delete;
  StderrToFile& operator=(const StderrToFile&) = delete;

 private:
  int saved_;
  int file_;
};

TEST(AsyncLogging, LinesGoThroughAQueueAndAllAreWrittenAtTheEnd) {
  const tumble::test::TempDir dir;
  const std::string path = (dir.path() / "stderr.txt").string();
  const auto previous = spdlog::default_logger();
  {
    const StderrToFile redirect(path);
    const AsyncLogging logging(LogLevel::Info);
    EXPECT_NE(dynamic_cast<spdlog::async_logger*>(spdlog::default_logger_raw()), nullptr);
    for (int i = 0; i < 1000; ++i) spdlog::info("line {}", i);
  }
  spdlog::set_default_logger(previous);  // the session's end dropped every logger
  std::ifstream in(path);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::size_t lines = 0;
  for (std::size_t at = text.find("line "); at != std::string::npos; at = text.find("line ", at + 1)) ++lines;
  EXPECT_EQ(lines, 1000u);
  EXPECT_NE(text.find("line 999\n"), std::string::npos);
}

}  // namespace
}  // namespace tumble::daemon
