// sd_notify for Type=notify services: READY=1 once both sensors deliver,
// WATCHDOG=1 while it is healthy, STATUS=<one line>, STOPPING=1 at shutdown.
// Every call is a no-op when the process is not started by systemd (no
// NOTIFY_SOCKET), so tumbled runs the same by hand.
#pragma once

#include <chrono>
#include <optional>
#include <string_view>

namespace tumble::daemon {

class SystemdNotifier {
 public:
  SystemdNotifier();  // reads NOTIFY_SOCKET, WATCHDOG_USEC and WATCHDOG_PID once

  // True when a notification socket is configured.
  bool active() const { return active_; }
  // The unit's WatchdogSec= for this process; ping at half of it.
  std::optional<std::chrono::microseconds> watchdog_timeout() const { return watchdog_; }

  // Each returns false when the message could not be sent (and nothing else
  // happens: the caller logs it); true also when not under systemd.
  bool ready() const;
  bool watchdog() const;
  bool status(std::string_view line) const;
  bool stopping() const;

 private:
  bool send(std::string_view message) const;
  bool active_ = false;
  std::optional<std::chrono::microseconds> watchdog_;
};

}  // namespace tumble::daemon
