// The page over HTTP and the live frames over a WebSocket (/ws), on one
// thread (the caller of run()). Serves only the files it names: the page's
// own from web_dir, three.js and its orbit controls from three_dir (Debian's
// libjs-three). Each browser has a bounded queue (OutboundQueue): a slow or
// stalled one drops its old frames and never holds up the others. Browsers
// cannot send anything that reaches LCM.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <memory>
#include <set>
#include <string>

#include "tools/view/frames.hpp"
#include "tools/view/live_state.hpp"

namespace tumble::view {

class WebSocketSession;

struct WebServerOptions {
  boost::asio::ip::tcp::endpoint listen;
  std::string web_dir;
  std::string three_dir;
  std::string lcm_url;         // for the link report
  std::string channel_prefix;
};

class WebServer {
 public:
  // Binds now (throws boost::system::system_error when it cannot).
  WebServer(boost::asio::io_context& io, WebServerOptions options, LiveState& state);
  unsigned short port() const;

  // Hands pending frames over to the browsers; safe from any thread.
  void notify_pending();

  // Session bookkeeping (web thread).
  void joined(const std::shared_ptr<WebSocketSession>& session);
  void left(WebSocketSession* session);
  // The file for a request target, or empty when it is not one the page uses.
  std::string file_for(const std::string& target) const;

 private:
  void accept();
  void broadcast_pending();
  void report_link();

  boost::asio::io_context& io_;
  WebServerOptions options_;
  LiveState& state_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer link_timer_;
  std::set<std::shared_ptr<WebSocketSession>> sessions_;
};

}  // namespace tumble::view
