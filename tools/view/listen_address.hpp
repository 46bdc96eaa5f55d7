// --listen ADDRESS:PORT as an endpoint: an IPv4 address, or an IPv6 one in
// brackets ([::1]:8076); port 0 picks a free one.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <optional>
#include <string>

namespace tumble::view {

std::optional<boost::asio::ip::tcp::endpoint> parse_listen_address(const std::string& text);

}  // namespace tumble::view
