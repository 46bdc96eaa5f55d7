// tumble-view in a real browser: Debian's Chromium, headless, loads the page
// while tumbled replays a simulated run, all inside a private network
// namespace (in_private_network.sh: LCM's udpm with ttl=0 on a loopback of
// its own). Skips where no browser can start.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test/daemon/process.hpp"
#include "test/temp_dir.hpp"
#include "test/tools/view/browser/devtools_client.hpp"
#include "test/tools/view/browser/png_image.hpp"

namespace tumble::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

const std::string kBin = TUMBLE_BINARY_DIR;
const std::vector<std::string> kTumbledStates = {"WAITING FOR SENSORS", "INITIALISING", "TRACKING", "DEGRADED",
                                                  "LOST"};

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool wait_for(const std::function<bool()>& condition, std::chrono::seconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    if (condition()) return true;
    std::this_thread::sleep_for(250ms);
  }
  return condition();
}

// A child process, ended (SIGTERM) when this goes.
class Child {
 public:
  Child(const std::vector<std::string>& argv, const fs::path& log_stem)
      : out_(log_stem.string() + ".out"), err_(log_stem.string() + ".err"),
        pid_(spawn_process(argv, {}, out_, err_)) {}
  ~Child() { stop(); }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  void stop() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    wait_process(pid_);
    pid_ = -1;
  }
  std::string out() const { return read_text(out_); }
  std::string err() const { return read_text(err_); }

 private:
  std::string out_, err_;
  int pid_;
};

// What the page shows, as its DOM and tumbleView say.
struct PageView {
  std::string state, pose;
  long scans = 0, scan_points = 0, last_scan_index = -1, poses = 0, map_points = 0;
  bool connected = false;
  std::string banner;  // "", "multicast" (the no-traffic help) or "other"
  bool shows_tumbled_state() const {
    return std::find(kTumbledStates.begin(), kTumbledStates.end(), state) != kTumbledStates.end();
  }
};

PageView look(DevToolsClient& page) {
  const std::string text = page.evaluate(
      "(() => { const t = id => document.getElementById(id); const v = window.tumbleView || {};"
      " const b = t('banner'); return [t('state-name').textContent, t('pose').textContent, v.scans, v.scanPoints,"
      " v.lastScanIndex, v.poses, v.connected, v.mapPoints, b.hidden ? '' : (b.textContent.includes('multicast') ?"
      " 'multicast' : 'other')].join('|'); })()");
  std::vector<std::string> f;
  std::stringstream in(text);
  for (std::string field; std::getline(in, field, '|');) f.push_back(field);
  PageView v;
  if (f.size() < 8) return v;
  v.state = f[0];
  v.pose = f[1];
  v.scans = std::atol(f[2].c_str());
  v.scan_points = std::atol(f[3].c_str());
  v.last_scan_index = std::atol(f[4].c_str());
  v.poses = std::atol(f[5].c_str());
  v.connected = f[6] == "true";
  v.map_points = std::atol(f[7].c_str());
  v.banner = f.size() > 8 ? f[8] : "";
  return v;
}

std::string describe(const PageView& v) {
  return "state '" + v.state + "', pose '" + v.pose + "', scans " + std::to_string(v.scans) + " (" +
         std::to_string(v.scan_points) + " points), map " + std::to_string(v.map_points) + " points, poses " +
         std::to_string(v.poses) + ", last scan " + std::to_string(v.last_scan_index) +
         (v.connected ? ", connected" : ", disconnected") + ", banner '" + v.banner + "'";
}

class ViewInBrowser : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("view-browser");
    const ProcessResult sim = run_process({kBin + "/tools/sim/tumble-sim", "run", "--out", (dir_->path() / "run").string()});
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  static void TearDownTestSuite() { delete dir_; }

  static std::unique_ptr<Child> start_view(const std::string& listen, const std::string& name) {
    return std::make_unique<Child>(
        std::vector<std::string>{kBin + "/tools/view/tumble-view", "--listen", listen}, dir_->path() / name);
  }
  // At half speed: the 11 s default run lasts long enough for the view to restart during it.
  static std::unique_ptr<Child> start_tumbled(const std::string& name) {
    const fs::path run = dir_->path() / "run";
    return std::make_unique<Child>(
        std::vector<std::string>{kBin + "/daemon/tumbled", "--replay", (run / "lidar.pcap").string(),
                                 (run / "imu.pcap").string(), "--rate", "0.5", "--set", "lcm.publish_scan=true",
                                 "--set", "lcm.publish_map_period_s=1"},
        dir_->path() / name);
  }

  static TempDir* dir_;
};

TempDir* ViewInBrowser::dir_ = nullptr;

TEST_F(ViewInBrowser, ShowsTheStatePoseAndScanOfAReplayAndRecoversAfterTheViewAndTumbledRestart) {
  if (::access(TUMBLE_CHROMIUM, X_OK) != 0)
    GTEST_SKIP() << "no browser: " << TUMBLE_CHROMIUM
                 << " is not installed (Debian package chromium; ./tumble test installs it)";
  auto view = start_view("127.0.0.1:0", "view1");
  std::smatch address;
  static const std::regex kAddress(R"(open http://127\.0\.0\.1:(\d+)/)");
  ASSERT_TRUE(wait_for([&] {
    const std::string out = view->out();
    return std::regex_search(out, address, kAddress);
  }, 10s)) << "tumble-view printed no address: " << view->out() << view->err();
  const std::string port = address[1].str();
  auto tumbled = start_tumbled("tumbled1");

  const fs::path profile = dir_->path() / "chromium-profile";
  fs::create_directories(profile);
  Child browser({TUMBLE_CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
                 "--disable-quic", "--no-first-run", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--user-data-dir=" + profile.string(), "--remote-debugging-port=0",
                 "--window-size=1280,800", "http://127.0.0.1:" + port + "/"},
                dir_->path() / "chromium");
  const fs::path active_port = profile / "DevToolsActivePort";
  if (!wait_for([&] { return fs::exists(active_port) && !read_text(active_port).empty(); }, 30s))
    GTEST_SKIP() << "no browser could start (" << TUMBLE_CHROMIUM << "): " << browser.err().substr(0, 2000);
  DevToolsClient page(static_cast<unsigned short>(std::stoi(read_text(active_port))));

  // The replay as it goes: tumbled's state, the pose, a scan and the map drawn.
  PageView v;
  ASSERT_TRUE(wait_for([&] {
    v = look(page);
    return v.shows_tumbled_state() && v.pose.starts_with("x ") && v.scan_points > 0 && v.map_points > 0;
  }, 40s)) << describe(v) << "\ntumble-view: " << view->err() << "\ntumbled: " << tumbled->err().substr(0, 3000);
  const std::optional<RgbaImage> shot = decode_png(page.screenshot_png());
  ASSERT_TRUE(shot) << "the screenshot is no PNG this test reads";
  // The panel is 380 px on the right (view.css), its scroll bar left of it:
  // what is left of that is the 3D view. Its axes and trajectory alone are
  // about a thousand pixels; the scan and the map tens of thousands.
  const int scene_width = shot->width - 420;
  int drawn = 0;
  for (int y = 0; y < shot->height; ++y)
    for (int x = 0; x < scene_width; ++x) {
      const std::uint8_t* p = shot->at(x, y);
      if (std::abs(p[0] - 0x10) + std::abs(p[1] - 0x14) + std::abs(p[2] - 0x18) > 30) ++drawn;
    }
  EXPECT_GT(drawn, 5000) << "pixels of the 3D view that differ from its background, " << describe(v);
  std::printf("the 3D view drew %d pixels: %s\n", drawn, describe(v).c_str());

  // The view restarts: the page says so, then reconnects and goes on.
  view->stop();
  ASSERT_TRUE(wait_for([&] { return (v = look(page)).state == "DISCONNECTED" && !v.connected; }, 10s)) << describe(v);
  view = start_view("127.0.0.1:" + port, "view2");
  const long poses_before = v.poses;
  ASSERT_TRUE(wait_for([&] {
    v = look(page);
    return v.connected && v.shows_tumbled_state() && v.poses > poses_before + 5;
  }, 20s)) << describe(v) << "\ntumble-view: " << view->err();

  // tumbled stops: the page says no traffic comes, with the likely causes.
  const long last_index_of_first_run = v.last_scan_index;
  tumbled->stop();
  ASSERT_TRUE(wait_for([&] { return (v = look(page)).state == "NO DATA" && v.banner == "multicast"; }, 10s))
      << describe(v);
  // tumbled starts again: a new trajectory, tumbled's state again.
  tumbled = start_tumbled("tumbled2");
  ASSERT_TRUE(wait_for([&] {
    v = look(page);
    return v.shows_tumbled_state() && v.banner.empty() && v.last_scan_index >= 0 &&
           v.last_scan_index < last_index_of_first_run && v.poses > 0;
  }, 30s)) << describe(v) << " (the first run ended at scan " << last_index_of_first_run << ")";
}

}  // namespace
}  // namespace tumble::test
