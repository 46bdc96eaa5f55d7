// scan_correction_of: every field the fuser reads comes from the scan's result.

#include "core/scan_registration.hpp"

#include <gtest/gtest.h>

namespace tumble {
namespace {

TEST(ScanCorrectionOf, CarriesEveryFieldTheFuserReads) {
  ScanResult result;
  result.t_scan_start_s = 12.5;
  result.t_scan_end_s = 12.6;
  result.T_wl.translation() = Eigen::Vector3d(1, 2, 3);
  result.T_wl.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  result.position_sigma_m = 0.004;
  result.position_var_w_m2 = Eigen::Vector3d(1e-4, 2e-4, 3e-4);
  result.jumped = true;
  result.map_initialised = true;
  result.expected_error_icp_m = 0.021;
  result.expected_error_m = 0.5;  // the published one: not what the fuser levels by
  result.expected_rotation_error_icp_rad = 0.002;
  result.held_translation_w = Eigen::Vector3d::UnitX();

  const ScanCorrection c = scan_correction_of(result);
  EXPECT_EQ(c.t_start_s, 12.5);
  EXPECT_EQ(c.t_end_s, 12.6);
  EXPECT_TRUE(c.T_wl.isApprox(result.T_wl, 0.0));
  EXPECT_EQ(c.position_sigma_m, 0.004);
  EXPECT_EQ(c.position_var_w_m2, result.position_var_w_m2);
  EXPECT_TRUE(c.jumped);
  EXPECT_TRUE(c.map_start);
  EXPECT_EQ(c.expected_error_m, 0.021);
  EXPECT_EQ(c.expected_rotation_error_rad, 0.002);
  EXPECT_EQ(c.unmeasured_w, Eigen::Vector3d::UnitX());
}

}  // namespace
}  // namespace tumble
