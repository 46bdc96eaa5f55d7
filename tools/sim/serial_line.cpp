#include "tools/sim/serial_line.hpp"

#include <algorithm>

namespace tumble::sim {

void SerialLine::send(double ready_s, std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return;
  const double start_s = std::max(ready_s, line_free_s_);
  queue_.push_back(Message{start_s, std::vector<std::uint8_t>(bytes.begin(), bytes.end())});
  line_free_s_ = start_s + static_cast<double>(bytes.size()) * byte_time_s_;
}

std::optional<double> SerialLine::first_unread_arrival_s() const {
  if (queue_.empty()) return std::nullopt;
  const Message& m = queue_.front();
  return m.start_s + static_cast<double>(m.read + 1) * byte_time_s_;
}

void SerialLine::read_until(double t_s, std::size_t max_bytes, std::vector<std::uint8_t>& out) {
  std::size_t taken = 0;
  while (!queue_.empty() && taken < max_bytes) {
    Message& m = queue_.front();
    // Bytes [0, arrived) of this message are on the host by t_s (the epsilon
    // keeps a read at exactly a byte's arrival time from missing it).
    const double elapsed = (t_s - m.start_s) / byte_time_s_ + 1e-6;
    const auto arrived = static_cast<std::size_t>(std::clamp(elapsed, 0.0, static_cast<double>(m.bytes.size())));
    const std::size_t n = std::min(arrived > m.read ? arrived - m.read : 0, max_bytes - taken);
    out.insert(out.end(), m.bytes.begin() + static_cast<std::ptrdiff_t>(m.read),
               m.bytes.begin() + static_cast<std::ptrdiff_t>(m.read + n));
    m.read += n;
    taken += n;
    if (m.read < m.bytes.size()) break;
    queue_.pop_front();
  }
}

}  // namespace tumble::sim
