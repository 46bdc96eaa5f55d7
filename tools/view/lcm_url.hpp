// The LCM URL the view opens. A scan and a map message arrive back to back,
// a few hundred kB of UDP fragments in a millisecond: the kernel's default
// receive buffer (212 kB) drops the second. So a udpm URL that sets no
// recv_buf_size gets 4 MB (the kernel caps it at net.core.rmem_max; the
// package's sysctl file raises that to 8 MB).
#pragma once

#include <string>

namespace tumble::view {

inline constexpr int kReceiveBufferBytes = 4 << 20;

std::string with_receive_buffer(const std::string& lcm_url);

}  // namespace tumble::view
