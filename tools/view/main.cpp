// tumble-view: watch tumbled live in a browser. Subscribes to tumbled's LCM
// channels (sending nothing on LCM) and serves one page with the trajectory,
// the pose, the newest scan, the local map and the health.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "tools/view/lcm_source.hpp"
#include "tools/view/lcm_url.hpp"
#include "tools/view/listen_address.hpp"
#include "tools/view/live_state.hpp"
#include "tools/view/web_server.hpp"
#include "tumble_build_info.hpp"

namespace {

// The page's files: installed beside the program (share/tumble/view), else
// the source tree's (a build tree's program).
std::string default_web_dir(const char* argv0) {
  std::error_code ec;
  const auto exe = std::filesystem::canonical("/proc/self/exe", ec);
  const auto installed = (ec ? std::filesystem::path(argv0) : exe).parent_path() / "../share/tumble/view";
  if (std::filesystem::exists(installed / "index.html", ec)) return std::filesystem::weakly_canonical(installed).string();
  return TUMBLE_VIEW_SOURCE_WEB_DIR;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tumble-view: tumbled's pose, health, scan and map live in a browser (read-only on LCM)"};
  app.set_version_flag("--version", std::string("tumble-view ") + tumble::kVersion)->trigger_on_parse();
  std::string listen = "127.0.0.1:8076";
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  std::string prefix = "TUMBLE_";
  std::string web_dir = default_web_dir(argv[0]);
  std::string three_dir = "/usr/share/javascript/three";
  app.add_option("--listen", listen, "ADDRESS:PORT to serve the page on (port 0: any free one)")->capture_default_str();
  app.add_option("--lcm-url", lcm_url,
                 "LCM URL tumbled publishes on (its lcm.url; a udpm URL without recv_buf_size gets 4 MB)")
      ->capture_default_str();
  app.add_option("--channel-prefix", prefix, "tumbled's lcm.channel_prefix")->capture_default_str();
  app.add_option("--web-dir", web_dir, "the page's files")->capture_default_str();
  app.add_option("--three-dir", three_dir, "three.js (Debian's libjs-three)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const auto endpoint = tumble::view::parse_listen_address(listen);
  if (!endpoint) {
    spdlog::error("--listen {}: expected ADDRESS:PORT, e.g. 127.0.0.1:8076 or [::1]:8076", listen);
    return 2;
  }
  try {
    boost::asio::io_context io;
    tumble::view::LiveState state;
    tumble::view::WebServer server(io, {*endpoint, web_dir, three_dir, lcm_url, prefix}, state);
    state.on_pending([&server] { server.notify_pending(); });
    tumble::view::LcmSource source(tumble::view::with_receive_buffer(lcm_url), prefix, state);
    source.start();
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&io](const boost::system::error_code&, int) { io.stop(); });
    const auto address = endpoint->address();
    const std::string host = address.is_v6() ? "[" + address.to_string() + "]" : address.to_string();
    std::printf("tumble-view: open http://%s:%u/ (LCM %s, channels %s*)\n", host.c_str(), server.port(),
                lcm_url.c_str(), prefix.c_str());
    std::fflush(stdout);
    io.run();
    source.stop();
  } catch (const std::exception& e) {
    spdlog::error("tumble-view: {}", e.what());
    return 1;
  }
  return 0;
}
