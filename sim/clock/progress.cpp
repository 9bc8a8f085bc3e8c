#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace rnav {

ProgressBar::ProgressBar(std::string label) : label_(std::move(label)), tty_(isatty(2) != 0) {}

void ProgressBar::update(int done, int total, int retries, double now_s) {
  if (start_s_ < 0) start_s_ = now_s;
  const double elapsed = now_s - start_s_;
  const double frac = total > 0 ? static_cast<double>(done) / total : 1.0;
  const double eta = done > 0 ? elapsed * (total - done) / done : 0.0;
  if (tty_) {
    const int width = 30, fill = static_cast<int>(frac * width);
    std::fprintf(stderr, "\r%s [%.*s%*s] %d/%d  %.1f s elapsed  ETA %.1f s  retries %d   ",
                 label_.c_str(), fill, "##############################", width - fill, "", done,
                 total, elapsed, eta, retries);
    if (done == total) std::fprintf(stderr, "\n");
  } else {
    const int decile = static_cast<int>(frac * 10);
    if (decile != last_decile_ || done == total) {
      last_decile_ = decile;
      std::fprintf(stderr, "%s %d/%d (%3.0f%%)  %.1f s elapsed  ETA %.1f s  retries %d\n",
                   label_.c_str(), done, total, frac * 100, elapsed, eta, retries);
    }
  }
  std::fflush(stderr);
}

}  // namespace rnav
