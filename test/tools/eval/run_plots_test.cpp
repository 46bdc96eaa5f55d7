#include "tools/eval/run_plots.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>

#include "test/temp_dir.hpp"

namespace tumble::eval {
namespace {

// Ground truth: 1 m/s along x for 4 s; the estimate the same motion in its own
// frame (turned 90° about z, elsewhere), drifting 1 cm/s along its own y.
void make_run(PoseSeries& truth, PoseSeries& estimate) {
  Eigen::Isometry3d estimate_frame = Eigen::Isometry3d::Identity();
  estimate_frame.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  estimate_frame.translation() = Eigen::Vector3d(5, -2, 1);
  for (int i = 0; i <= 400; ++i) {
    const double t = 100.0 + 0.01 * i;
    truth.push_back({t, Eigen::Vector3d(t - 100.0, 0, 0), Eigen::Quaterniond::Identity()});
    if (i % 10 == 0) {
      const Eigen::Vector3d drifted(t - 100.0, 0.01 * (t - 100.0), 0);
      estimate.push_back({t, estimate_frame * drifted, Eigen::Quaterniond(estimate_frame.linear())});
    }
  }
}

TEST(RunPlots, AlignsTheEstimateAtItsFirstPoseAndMeasuresTheErrorFromThere) {
  PoseSeries truth, estimate;
  make_run(truth, estimate);
  const std::vector<AlignedSample> samples = align_at_first_pose(truth, estimate);
  ASSERT_EQ(samples.size(), 41u);
  EXPECT_NEAR(samples.front().error_m, 0.0, 1e-9);
  EXPECT_NEAR(samples.back().estimate_m.x(), 4.0, 1e-9);
  EXPECT_NEAR(samples.back().estimate_m.y(), 0.04, 1e-9);
  EXPECT_NEAR(samples.back().error_m, 0.04, 1e-9);
}

TEST(RunPlots, DrawsTheTopAndSideViewsAndTheErrorAsPngs) {
  if (::access("/usr/bin/gnuplot", X_OK) != 0) GTEST_SKIP() << "gnuplot not installed (Debian package gnuplot-nox)";
  PoseSeries truth, estimate;
  make_run(truth, estimate);
  const test::TempDir dir("run-plots");
  ASSERT_EQ(draw_run_plots(truth, estimate, dir.path()), "");
  for (const char* name : {"trajectory_top.png", "trajectory_side.png", "error.png"}) {
    std::ifstream in(dir.path() / name, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 1000u) << name;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << name;
  }
}

TEST(RunPlots, SaysWhyWhenTheRunsDoNotOverlap) {
  PoseSeries truth, estimate;
  make_run(truth, estimate);
  for (TimedPose& p : estimate) p.t_s += 1000.0;
  const test::TempDir dir("run-plots");
  EXPECT_NE(draw_run_plots(truth, estimate, dir.path()), "");
}

}  // namespace
}  // namespace tumble::eval
