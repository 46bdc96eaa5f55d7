// Drives a page in a headless Chromium over the DevTools protocol: evaluates
// JavaScript in it and takes screenshots. Synchronous; a test's ctest
// timeout bounds a browser that stops answering.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/websocket/stream.hpp>
#include <string>

namespace tumble::test {

class DevToolsClient {
 public:
  // port: Chromium's --remote-debugging-port (its DevToolsActivePort file).
  // Connects to the first page target. Throws std::runtime_error.
  explicit DevToolsClient(unsigned short port);

  // The value of a JavaScript expression that yields a string ("" when it threw).
  std::string evaluate(const std::string& expression);
  // A PNG of the page as it is.
  std::string screenshot_png();

 private:
  std::string call(const std::string& method, const std::string& params_json);

  boost::asio::io_context io_;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  int next_id_ = 1;
};

// The string after "key":" in a JSON text, unescaped (enough for the
// DevTools answers a test reads); empty when absent.
std::string json_string_field(const std::string& json, const std::string& key);

}  // namespace tumble::test
