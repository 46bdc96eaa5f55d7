// A tumbled subscriber in C++: prints the lidar pose T_WL from TUMBLE_ODOM
// while tumbled says it can be trusted, each state change from TUMBLE_STATUS,
// and each re-initialisation (a new local map).
//   tumble_subscriber_example [--lcm-url URL] [--prefix TUMBLE_] [--poses N] [--timeout-s T]
// Exits 0 after N trusted poses (0, the default: runs until interrupted),
// 1 when T seconds pass first, 2 on a bad command line.
#include <lcm/lcm-cpp.hpp>
#include <tumble/odometry_t.hpp>
#include <tumble/status_t.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

struct Options {
  std::string lcm_url;  // "": LCM's default (udpm://239.255.76.67:7667?ttl=0, tumbled's too)
  std::string prefix = "TUMBLE_";
  long poses = 0;
  double timeout_s = 0;  // 0: none
};

class Subscriber {
 public:
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const tumble::status_t* status) {
    if (status->state != state_)
      std::printf("state %s: %s\n", status->state_name.c_str(), status->state_reason.c_str());
    state_ = status->state;
  }

  void on_odometry(const lcm::ReceiveBuffer*, const std::string&, const tumble::odometry_t* odometry) {
    // A new local map: the poses after it do not continue those before.
    if (resets_ >= 0 && odometry->resets != resets_)
      std::printf("re-initialised (resets %d): the trajectory is discontinuous here\n", odometry->resets);
    resets_ = odometry->resets;
    if (!trusted(*odometry)) return;
    ++trusted_poses_;
    const double* p = odometry->position_m;
    const double* q = odometry->orientation;  // w, x, y, z of W <- L
    std::printf("%.6f s  p_W %.3f %.3f %.3f m  q_WL (w x y z) %.4f %.4f %.4f %.4f\n", odometry->utime * 1e-6,
                p[0], p[1], p[2], q[0], q[1], q[2], q[3]);
  }

  long trusted_poses() const { return trusted_poses_; }

 private:
  // TUMBLE_STATUS says tracking, and the sample is from an initialised fuser
  // that is not waiting for the robot to rest after a loss of track.
  bool trusted(const tumble::odometry_t& odometry) const {
    return state_ == tumble::status_t::STATE_TRACKING &&
           (odometry.flags & tumble::odometry_t::FLAG_INITIALISED) != 0 &&
           (odometry.flags & tumble::odometry_t::FLAG_AWAITING_REST) == 0;
  }

  int state_ = -1;   // none received yet
  int resets_ = -1;  // none received yet
  long trusted_poses_ = 0;
};

bool parse(int argc, char** argv, Options& options) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--lcm-url") options.lcm_url = value;
    else if (flag == "--prefix") options.prefix = value;
    else if (flag == "--poses") options.poses = std::atol(value.c_str());
    else if (flag == "--timeout-s") options.timeout_s = std::atof(value.c_str());
    else return false;
  }
  return argc % 2 == 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, options)) {
    std::fprintf(stderr, "usage: %s [--lcm-url URL] [--prefix TUMBLE_] [--poses N] [--timeout-s T]\n", argv[0]);
    return 2;
  }
  lcm::LCM lcm(options.lcm_url);
  if (!lcm.good()) {
    std::fprintf(stderr, "LCM cannot start on %s\n", options.lcm_url.c_str());
    return 1;
  }
  Subscriber subscriber;
  lcm.subscribe(options.prefix + "STATUS", &Subscriber::on_status, &subscriber);
  lcm.subscribe(options.prefix + "ODOM", &Subscriber::on_odometry, &subscriber);
  std::printf("listening\n");
  std::fflush(stdout);

  const auto start = std::chrono::steady_clock::now();
  while (options.poses == 0 || subscriber.trusted_poses() < options.poses) {
    lcm.handleTimeout(100);
    std::fflush(stdout);
    const std::chrono::duration<double> waited = std::chrono::steady_clock::now() - start;
    if (options.timeout_s > 0 && waited.count() > options.timeout_s) {
      std::fprintf(stderr, "%ld trusted poses in %.0f s, not %ld\n", subscriber.trusted_poses(), options.timeout_s,
                    options.poses);
      return 1;
    }
  }
  return 0;
}
