#include "daemon/trajectory_file.hpp"

#include <fmt/format.h>

namespace tumble::daemon {

void TrajectoryFile::on_registration(const RegistrationRecord& r) {
  if (file_.get() == nullptr || !r.registered) return;
  const auto& q = r.orientation_wxyz;
  fmt::print(file_.get(), "{:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f}\n", r.t_s, r.position_m[0],
             r.position_m[1], r.position_m[2], q[1], q[2], q[3], q[0]);
}

}  // namespace tumble::daemon
