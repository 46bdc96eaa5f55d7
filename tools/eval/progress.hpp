// Progress and ETA on stderr, one line per finished job. The ETA weighs jobs
// by the simulated duration of their run (replay time grows with it).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace tumble::eval {

// "42 s", "3 min 05 s", "1 h 02 min".
std::string format_duration(double seconds);

class Progress {
 public:
  Progress(std::size_t jobs, double total_weight, std::FILE* out);

  // Prints "[done/jobs] what | elapsed, ETA". A job that never ran (bad
  // input) leaves the ETA's rate alone: its weight is dropped from the total.
  void job_finished(double weight, bool ran, const std::string& what);

 private:
  std::size_t jobs_;
  std::size_t done_ = 0;
  double total_weight_;
  double done_weight_ = 0.0;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace tumble::eval
