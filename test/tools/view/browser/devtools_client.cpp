#include "test/tools/view/browser/devtools_client.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <regex>
#include <stdexcept>

#include "test/tools/view/browser/png_image.hpp"
#include "tools/view/frames.hpp"

namespace tumble::test {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

namespace {

std::string http_get(asio::io_context& io, unsigned short port, const std::string& target) {
  beast::tcp_stream stream(io);
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, "127.0.0.1");
  http::write(stream, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(stream, buffer, response);
  return response.body();
}

}  // namespace

std::string json_string_field(const std::string& json, const std::string& key) {
  const std::string start = "\"" + key + "\":\"";
  auto at = json.find(start);
  if (at == std::string::npos) return {};
  std::string out;
  for (at += start.size(); at < json.size() && json[at] != '"'; ++at) {
    if (json[at] != '\\' || at + 1 >= json.size()) {
      out += json[at];
      continue;
    }
    const char escaped = json[++at];
    out += escaped == 'n' ? '\n' : escaped == 't' ? '\t' : escaped;
  }
  return out;
}

DevToolsClient::DevToolsClient(unsigned short port) : ws_(io_) {
  const std::string targets = http_get(io_, port, "/json/list");
  static const std::regex kPage(R"re("type":\s*"page",[^}]*"webSocketDebuggerUrl":\s*"ws://[^/]+(/devtools/page/[^"]+)")re");
  std::smatch match;
  if (!std::regex_search(targets, match, kPage)) throw std::runtime_error("no page target in " + targets);
  beast::get_lowest_layer(ws_).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  ws_.read_message_max(64 << 20);
  ws_.handshake("127.0.0.1:" + std::to_string(port), match[1].str());
}

std::string DevToolsClient::call(const std::string& method, const std::string& params_json) {
  const int id = next_id_++;
  ws_.text(true);
  ws_.write(asio::buffer("{\"id\":" + std::to_string(id) + ",\"method\":\"" + method + "\",\"params\":" + params_json +
                         "}"));
  const std::string answer_start = "{\"id\":" + std::to_string(id) + ",";
  for (;;) {  // events come in between; the answer carries our id
    beast::flat_buffer buffer;
    ws_.read(buffer);
    std::string message = beast::buffers_to_string(buffer.data());
    if (message.starts_with(answer_start)) return message;
  }
}

std::string DevToolsClient::evaluate(const std::string& expression) {
  return json_string_field(
      call("Runtime.evaluate", "{\"expression\":" + view::json_string(expression) + ",\"returnByValue\":true}"),
      "value");
}

std::string DevToolsClient::screenshot_png() {
  return decode_base64(json_string_field(call("Page.captureScreenshot", R"({"format":"png"})"), "data"));
}

}  // namespace tumble::test
