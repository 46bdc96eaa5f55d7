#include "daemon/thread_setup.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
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

std::string lower_this_thread_priority(int increment) {
  if (increment <= 0) return {};
  const auto tid = static_cast<id_t>(gettid());
  errno = 0;
  const int current = getpriority(PRIO_PROCESS, tid);
  if (current == -1 && errno != 0) return std::string("reading the nice value: ") + std::strerror(errno);
  if (setpriority(PRIO_PROCESS, tid, current + increment) == 0) return {};
  return std::string("nice +") + std::to_string(increment) + ": " + std::strerror(errno);
}

}  // namespace tumble::daemon
