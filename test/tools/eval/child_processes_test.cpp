#include "tools/eval/child_processes.hpp"

#include <gtest/gtest.h>

#include <csignal>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::read_file;
using test::TempDir;

ChildCommand shell(const std::string& script, const std::filesystem::path& log, double timeout_s = 60.0) {
  return ChildCommand{{"/bin/sh", "-c", script}, log, timeout_s};
}

TEST(ChildProcesses, ReportsExitCodeOutputAndPeakRss) {
  const TempDir dir("child");
  const ChildOutcome outcome = run_child(shell("echo out; echo err >&2; exit 3", dir.path() / "log"));
  EXPECT_FALSE(outcome.succeeded());
  EXPECT_EQ(outcome.exit_code, 3);
  EXPECT_EQ(outcome.describe(), "exit code 3");
  EXPECT_GT(outcome.peak_rss_kib, 0);
  EXPECT_EQ(read_file(dir.path() / "log"), "out\nerr\n");
  EXPECT_TRUE(run_child(shell("exit 0", dir.path() / "log")).succeeded());
}

TEST(ChildProcesses, ACommandThatCannotStartIsReportedNotThrown) {
  const TempDir dir("child");
  const ChildOutcome outcome = run_child(ChildCommand{{"/nonexistent/tumbled"}, dir.path() / "log", 60.0});
  EXPECT_FALSE(outcome.succeeded());
  EXPECT_NE(outcome.describe().find("cannot start /nonexistent/tumbled"), std::string::npos) << outcome.describe();
  const ChildOutcome no_log = run_child(shell("exit 0", dir.path() / "no" / "such" / "dir" / "log"));
  EXPECT_FALSE(no_log.succeeded());
}

TEST(ChildProcesses, RunsSeveralAndReportsEachByItsId) {
  const TempDir dir("child");
  ChildPool pool;
  for (std::size_t id = 0; id < 3; ++id)
    pool.start(id, shell("exit " + std::to_string(10 + id), dir.path() / ("log" + std::to_string(id))));
  std::vector<int> codes(3, -1);
  while (pool.running() > 0)
    for (const auto& [id, outcome] : pool.wait(std::chrono::seconds(5))) codes[id] = outcome.exit_code;
  EXPECT_EQ(codes, (std::vector<int>{10, 11, 12}));
}

TEST(ChildProcesses, KillsAChildThatOverrunsItsTimeLimit) {
  const TempDir dir("child");
  const ChildOutcome outcome = run_child(shell("exec sleep 600", dir.path() / "log", 0.05));
  EXPECT_TRUE(outcome.timed_out);
  EXPECT_EQ(outcome.signal, SIGKILL);
  EXPECT_NE(outcome.describe().find("time limit"), std::string::npos);
}

}  // namespace
}  // namespace tumble::eval
