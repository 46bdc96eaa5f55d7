#include "daemon/thread_setup.hpp"

#include <pthread.h>
#include <sched.h>

#include <cstring>

namespace tumble::daemon {

void name_this_thread(const std::string& name) { pthread_setname_np(pthread_self(), name.substr(0, 15).c_str()); }

std::string set_realtime_priority(int priority) {
  if (priority <= 0) return {};
  sched_param param{};
  param.sched_priority = priority;
  const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (error == 0) return {};
  return std::string("SCHED_FIFO priority ") + std::to_string(priority) + ": " + std::strerror(error) +
         " (allow it with LimitRTPRIO= in the unit, or CAP_SYS_NICE)";
}

}  // namespace tumble::daemon
