#include "tools/view/lcm_url.hpp"

namespace tumble::view {

std::string with_receive_buffer(const std::string& url) {
  if (!url.starts_with("udpm://") || url.find("recv_buf_size=") != std::string::npos) return url;
  const char separator = url.find('?') == std::string::npos ? '?' : '&';
  return url + separator + "recv_buf_size=" + std::to_string(kReceiveBufferBytes);
}

}  // namespace tumble::view
