// A UART as the host sees it: bytes leave one after another at baud/10 bytes
// per second (8N1), and each tty read returns whatever has arrived by then.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

namespace tumble::sim {

class SerialLine {
 public:
  explicit SerialLine(int baud) : byte_time_s_(10.0 / baud) {}

  // The device starts sending these bytes at ready_s, or when the line is
  // free if an earlier message is still going out.
  void send(double ready_s, std::span<const std::uint8_t> bytes);

  // When the first byte not yet read has fully arrived; nullopt when none is queued.
  std::optional<double> first_unread_arrival_s() const;

  // Appends to out every queued byte that has arrived by t_s (at most max_bytes).
  void read_until(double t_s, std::size_t max_bytes, std::vector<std::uint8_t>& out);

 private:
  struct Message {
    double start_s;
    std::vector<std::uint8_t> bytes;
    std::size_t read = 0;
  };
  double byte_time_s_;
  double line_free_s_ = 0.0;
  std::deque<Message> queue_;
};

}  // namespace tumble::sim
