#include "daemon/scan_log.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "test/daemon/good_registration.hpp"
#include "test/temp_dir.hpp"
#include "tools/eval/scan_log.hpp"

namespace tumble::daemon {
namespace {

// A registered scan the health machine calls good under the default limits.
RegistrationRecord good_scan_record(std::int64_t index) {
  RegistrationRecord r = good_registration();
  r.scan_index = index;
  r.t_s = 100.0 + 0.1 * static_cast<double>(index);
  r.num_stages = 2;  // as the registration stage reports them: one time per stage name
  r.stage_ms[0] = 1.0f;
  r.stage_ms[1] = 2.0f;
  return r;
}

TEST(ScanLogTest, EachScanSaysWhetherTheHealthMachineCalledItGoodUnderTheConfigsLimits) {
  const test::TempDir dir("scan-log");
  const auto path = dir.path() / "scans.csv";
  HealthConfig health;
  health.max_expected_error_m = 0.05;
  {
    ScanLog log(path.string(), {"deskew", "icp"}, health);
    log.on_registration(good_scan_record(0));
    RegistrationRecord spin = good_scan_record(1);
    spin.spin_rate_unmeasured = true;
    spin.spin_clipped_scans_in_row = 4;
    spin.matched_ratio = 0.27f;  // enough for a measured spin, not a clipped one
    spin.held_translation_w = {0.0f, -1.0f, 0.0f};
    spin.expected_rotation_error_icp_rad = 0.001f;  // 0.0573° in the log
    log.on_registration(spin);
    RegistrationRecord loose = good_scan_record(2);
    loose.expected_error_m = 0.045f;  // over the default 0.04, within this config's 0.05
    log.on_registration(loose);
    loose.scan_index = 3;
    loose.expected_error_m = 0.06f;
    log.on_registration(loose);
    RegistrationRecord unregistered = good_scan_record(4);
    unregistered.registered = false;
    log.on_registration(unregistered);
    log.commit();
  }
  // tumble-eval's reader: every row has the header's field count, or it throws.
  const eval::ScanLog written = eval::read_scan_log(path);
  EXPECT_EQ(written.column("good_scan"), (std::vector<double>{1, 0, 1, 0, 0}));
  EXPECT_EQ(written.column("spin_rate_unmeasured"), (std::vector<double>{0, 1, 0, 0, 0}));
  EXPECT_EQ(written.column("translation_held"), (std::vector<double>{0, 1, 0, 0, 0}));
  EXPECT_NEAR(written.column("expected_rotation_error_icp_deg")[1], 0.0573, 1e-5);
  EXPECT_EQ(written.column("icp_ms"), std::vector<double>(5, 2.0));
}

}  // namespace
}  // namespace tumble::daemon
