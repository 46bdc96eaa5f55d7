#include "tools/eval/progress.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::eval {

std::string format_duration(double seconds) {
  const long total = std::lround(std::max(0.0, seconds));
  char text[48];
  if (total < 60)
    std::snprintf(text, sizeof text, "%ld s", total);
  else if (total < 3600)
    std::snprintf(text, sizeof text, "%ld min %02ld s", total / 60, total % 60);
  else
    std::snprintf(text, sizeof text, "%ld h %02ld min", total / 3600, (total % 3600) / 60);
  return text;
}

Progress::Progress(std::size_t jobs, double total_weight, std::FILE* out)
    : jobs_(jobs), total_weight_(total_weight), out_(out) {}

void Progress::job_finished(double weight, bool ran, const std::string& what) {
  ++done_;
  if (ran)
    done_weight_ += weight;
  else
    total_weight_ -= weight;
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string eta = "done";
  if (done_ < jobs_)
    eta = done_weight_ > 0.0 ? "ETA " + format_duration(elapsed_s * (total_weight_ - done_weight_) / done_weight_)
                             : "ETA unknown";
  std::fprintf(out_, "eval: [%zu/%zu] %s | %s elapsed, %s\n", done_, jobs_, what.c_str(),
               format_duration(elapsed_s).c_str(), eta.c_str());
  std::fflush(out_);
}

}  // namespace tumble::eval
