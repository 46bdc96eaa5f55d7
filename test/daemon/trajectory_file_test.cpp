#include "daemon/trajectory_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

class TrajectoryFileTest : public ::testing::Test {
 protected:
  void TearDown() override {
    fs::remove(path_);
    fs::remove(path_.string() + ".partial");
  }
  fs::path path_ = fs::temp_directory_path() / ("tumble_traj_" + std::to_string(::getpid()) + ".tum");
};

TEST_F(TrajectoryFileTest, AppearsOnlyWhenCommitted) {
  {
    TrajectoryFile file(path_.string());
    RegistrationRecord r;
    r.t_s = 1700000000.5;
    r.position_m = {1.0, -2.0, 0.25};
    r.orientation_wxyz = {0.5, 0.5, -0.5, 0.5};
    r.registered = true;
    file.on_registration(r);
    RegistrationRecord unplaced = r;  // the registration failed: no pose to report
    unplaced.registered = false;
    unplaced.t_s += 0.1;
    file.on_registration(unplaced);
    EXPECT_FALSE(fs::exists(path_));
    EXPECT_TRUE(fs::exists(path_.string() + ".partial"));
    file.commit();
  }
  EXPECT_FALSE(fs::exists(path_.string() + ".partial"));
  std::ifstream in(path_);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "1700000000.500000 1.000000 -2.000000 0.250000 0.500000000 -0.500000000 0.500000000 0.500000000");
  EXPECT_FALSE(std::getline(in, line));
}

TEST_F(TrajectoryFileTest, WithoutCommitTheFinalNameNeverExists) {
  {
    TrajectoryFile file(path_.string());
    file.on_registration(RegistrationRecord{});
  }
  EXPECT_FALSE(fs::exists(path_));
}

TEST_F(TrajectoryFileTest, UncreatableFileThrows) {
  EXPECT_THROW(TrajectoryFile("/nonexistent/dir/out.tum"), std::system_error);
}

}  // namespace
}  // namespace tumble::daemon
