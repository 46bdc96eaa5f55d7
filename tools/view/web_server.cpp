#include "tools/view/web_server.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <fstream>
#include <iterator>
#include <sstream>
#include <utility>

namespace tumble::view {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

namespace {

constexpr std::size_t kFramesPerBrowser = 64;  // queued for one browser at most
constexpr std::size_t kMaxRequestFromBrowser = 4096;

std::string content_type(const std::string& path) {
  const auto ends_with = [&](const char* suffix) { return path.ends_with(suffix); };
  if (ends_with(".html")) return "text/html; charset=utf-8";
  if (ends_with(".js")) return "text/javascript; charset=utf-8";
  if (ends_with(".css")) return "text/css; charset=utf-8";
  return "application/octet-stream";
}

bool read_file(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

}  // namespace

class WebSocketSession : public std::enable_shared_from_this<WebSocketSession> {
 public:
  WebSocketSession(tcp::socket socket, WebServer& server)
      : ws_(std::move(socket)), server_(server), queue_(kFramesPerBrowser) {}

  void start(http::request<http::string_body> request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxRequestFromBrowser);
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->server_.joined(self);
      self->read();
    });
  }

  void send(FramePtr frame) {
    if (closed_) return;
    queue_.push(std::move(frame));
    if (!writing_) write_next();
  }

 private:
  // Browsers send nothing the view uses; reading keeps the close and ping
  // handshakes going and notices a browser that went away.
  void read() {
    ws_.async_read(incoming_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      self->incoming_.consume(self->incoming_.size());
      self->read();
    });
  }

  void write_next() {
    current_ = queue_.pop();
    writing_ = current_ != nullptr;
    if (!writing_) return;
    ws_.binary(current_->binary);
    ws_.async_write(asio::buffer(current_->bytes), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      self->write_next();
    });
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    server_.left(this);
  }

  websocket::stream<beast::tcp_stream> ws_;
  WebServer& server_;
  OutboundQueue queue_;
  FramePtr current_;
  beast::flat_buffer incoming_;
  bool writing_ = false;
  bool closed_ = false;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, WebServer& server) : stream_(std::move(socket)), server_(server) {}

  void read() {
    request_ = {};
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, request_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (!ec) self->respond();
    });
  }

 private:
  void respond() {
    if (websocket::is_upgrade(request_)) {
      if (request_.target() != "/ws") return;
      stream_.expires_never();
      std::make_shared<WebSocketSession>(stream_.release_socket(), server_)->start(std::move(request_));
      return;
    }
    auto response = std::make_shared<http::response<http::string_body>>();
    response->version(request_.version());
    response->keep_alive(request_.keep_alive());
    response->set(http::field::server, "tumble-view");
    response->set(http::field::cache_control, "no-cache");
    response->set("X-Content-Type-Options", "nosniff");
    const std::string path = server_.file_for(std::string(request_.target()));
    std::string body;
    if (request_.method() != http::verb::get && request_.method() != http::verb::head) {
      response->result(http::status::method_not_allowed);
    } else if (path.empty() || !read_file(path, body)) {
      response->result(http::status::not_found);
      response->set(http::field::content_type, "text/plain");
      response->body() = path.empty() ? "not found\n" : "missing " + path + " (is libjs-three installed?)\n";
    } else {
      response->result(http::status::ok);
      response->set(http::field::content_type, content_type(path));
      if (request_.method() == http::verb::get) response->body() = std::move(body);
    }
    response->prepare_payload();
    http::async_write(stream_, *response,
                      [self = shared_from_this(), response](beast::error_code ec, std::size_t) {
                        if (ec || !response->keep_alive()) {
                          beast::error_code ignored;
                          self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
                          return;
                        }
                        self->read();
                      });
  }

  beast::tcp_stream stream_;
  WebServer& server_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
};

WebServer::WebServer(asio::io_context& io, WebServerOptions options, LiveState& state)
    : io_(io), options_(std::move(options)), state_(state), acceptor_(io), link_timer_(io) {
  acceptor_.open(options_.listen.protocol());
  acceptor_.set_option(asio::socket_base::reuse_address(true));
  acceptor_.bind(options_.listen);
  acceptor_.listen(asio::socket_base::max_listen_connections);
  accept();
  report_link();
}

unsigned short WebServer::port() const { return acceptor_.local_endpoint().port(); }

void WebServer::accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!ec) std::make_shared<HttpSession>(std::move(socket), *this)->read();
    accept();
  });
}

void WebServer::notify_pending() {
  asio::post(io_, [this] { broadcast_pending(); });
}

void WebServer::broadcast_pending() {
  for (const FramePtr& frame : state_.take_pending())
    for (const auto& session : sessions_) session->send(frame);
}

void WebServer::report_link() {
  LinkReport link{options_.lcm_url, options_.channel_prefix, state_.messages(),
                  state_.since_last_s(LiveState::Clock::now()).value_or(-1.0), sessions_.size()};
  const auto frame = std::make_shared<const Frame>(link_frame(link));
  for (const auto& session : sessions_) session->send(frame);
  link_timer_.expires_after(std::chrono::seconds(1));
  link_timer_.async_wait([this](beast::error_code ec) {
    if (!ec) report_link();
  });
}

void WebServer::joined(const std::shared_ptr<WebSocketSession>& session) {
  sessions_.insert(session);
  for (FramePtr& frame : state_.joining_frames()) session->send(std::move(frame));
  spdlog::info("a browser joined ({} now)", sessions_.size());
}

void WebServer::left(WebSocketSession* session) {
  std::erase_if(sessions_, [&](const auto& s) { return s.get() == session; });
  spdlog::info("a browser left ({} now)", sessions_.size());
}

std::string WebServer::file_for(const std::string& target) const {
  const std::string path = target.substr(0, target.find('?'));
  if (path == "/" || path == "/index.html") return options_.web_dir + "/index.html";
  if (path == "/view.js" || path == "/view.css") return options_.web_dir + path;
  if (path == "/three/three.min.js") return options_.three_dir + "/build/three.min.js";
  if (path == "/three/OrbitControls.js") return options_.three_dir + "/examples/js/controls/OrbitControls.js";
  return {};
}

}  // namespace tumble::view
