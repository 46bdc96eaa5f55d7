#include "daemon/systemd_notify.hpp"

#include <systemd/sd-daemon.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace tumble::daemon {

SystemdNotifier::SystemdNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  active_ = socket != nullptr && socket[0] != '\0';
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0) watchdog_ = std::chrono::microseconds(usec);
}

bool SystemdNotifier::send(std::string_view message) const {
  if (!active_) return true;
  return sd_notify(0, std::string(message).c_str()) > 0;
}

bool SystemdNotifier::ready() const { return send("READY=1"); }
bool SystemdNotifier::watchdog() const { return send("WATCHDOG=1"); }
bool SystemdNotifier::status(std::string_view line) const {
  std::string message = "STATUS=" + std::string(line);
  std::replace(message.begin(), message.end(), '\n', ' ');  // one assignment per line in the protocol
  return send(message);
}
bool SystemdNotifier::stopping() const { return send("STOPPING=1"); }

}  // namespace tumble::daemon
