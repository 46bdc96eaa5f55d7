#include "daemon/trajectory_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "test/temp_dir.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

RegistrationRecord registered_at(double t_s) {
  RegistrationRecord r;
  r.t_s = t_s;
  r.position_m = {1.0, -2.0, 0.25};
  r.orientation_wxyz = {0.5, 0.5, -0.5, 0.5};
  r.registered = true;
  return r;
}

class TrajectoryFileTest : public ::testing::Test {
 protected:
  test::TempDir dir_{"traj"};
  fs::path path_ = dir_.path() / "out.tum";
  std::atomic<std::int64_t> lost_{0};
};

TEST_F(TrajectoryFileTest, AppearsOnlyWhenCommitted) {
  {
    TrajectoryFile file(path_.string(), 60.0, lost_);
    file.on_registration(registered_at(1700000000.5));
    RegistrationRecord unplaced = registered_at(1700000000.6);  // the registration failed: no pose to report
    unplaced.registered = false;
    file.on_registration(unplaced);
    EXPECT_FALSE(fs::exists(path_));
    EXPECT_TRUE(fs::exists(path_.string() + ".partial"));
    EXPECT_TRUE(file.commit());
  }
  EXPECT_FALSE(fs::exists(path_.string() + ".partial"));
  EXPECT_EQ(text_of(path_),
            "1700000000.500000 1.000000 -2.000000 0.250000 0.500000000 -0.500000000 0.500000000 0.500000000\n");
  EXPECT_EQ(lost_.load(), 0);
}

TEST_F(TrajectoryFileTest, WithoutCommitTheFinalNameNeverExists) {
  {
    TrajectoryFile file(path_.string(), 60.0, lost_);
    file.on_registration(registered_at(1.0));
  }
  EXPECT_FALSE(fs::exists(path_));
}

TEST_F(TrajectoryFileTest, UncreatableFileThrows) {
  EXPECT_THROW(TrajectoryFile("/nonexistent/dir/out.tum", 2.0, lost_), std::system_error);
}

// A power cut keeps what the last checkpoint made durable: the poses reach
// the disk within a checkpoint period, before any commit.
TEST_F(TrajectoryFileTest, CheckpointsMakeThePosesDurableWhileRunning) {
  TrajectoryFile file(path_.string(), 0.1, lost_);
  for (int i = 0; i < 20; ++i) file.on_registration(registered_at(100.0 + 0.1 * i));
  const fs::path partial = path_.string() + ".partial";
  const auto lines = [&partial] {
    const std::string text = text_of(partial);
    return std::count(text.begin(), text.end(), '\n');
  };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while ((lines() < 20 || file.checkpoints() == 0) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(lines(), 20);
  EXPECT_GE(file.checkpoints(), 1);
  file.on_registration(registered_at(102.0));
  EXPECT_TRUE(file.commit());
  EXPECT_EQ(lost_.load(), 0);
}

// /dev/full fails every write with ENOSPC, as a full disk does.
TEST_F(TrajectoryFileTest, WriteErrorsAreCountedAndFailTheCommit) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  fs::create_symlink("/dev/full", path_.string() + ".partial");
  TrajectoryFile file(path_.string(), 0.1, lost_);
  for (int i = 0; i < 7; ++i) file.on_registration(registered_at(100.0 + 0.1 * i));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (lost_.load() < 7 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(lost_.load(), 7);  // counted while running, for status_t
  file.on_registration(registered_at(101.0));
  EXPECT_FALSE(file.commit());
  EXPECT_EQ(lost_.load(), 8);
  EXPECT_EQ(file.checkpoints(), 0);
}

}  // namespace
}  // namespace tumble::daemon
