#include "progress.hpp"

#include <unistd.h>

namespace rnav {

ProgressBar::ProgressBar(std::string label) : ProgressBar(std::move(label), stderr, isatty(2) != 0) {}

ProgressBar::ProgressBar(std::string label, std::FILE* out, bool redraw)
    : label_(std::move(label)), out_(out), redraw_(redraw) {}

void ProgressBar::update(int done, int total, int retries, double now_s) {
  if (finished_) return;
  if (start_s_ < 0) start_s_ = now_s;
  const double elapsed = now_s - start_s_;
  const double frac = total > 0 ? static_cast<double>(done) / total : 1.0;
  const double eta = done > 0 ? elapsed * (total - done) / done : 0.0;
  finished_ = done >= total;
  if (redraw_) {
    const int width = 30, fill = static_cast<int>(frac * width);
    std::fprintf(out_, "\r%s [%.*s%*s] %d/%d  %.1f s elapsed  ETA %.1f s  retries %d   ",
                 label_.c_str(), fill, "##############################", width - fill, "", done,
                 total, elapsed, eta, retries);
    if (finished_) std::fprintf(out_, "\n");
  } else {
    const int decile = static_cast<int>(frac * 10);
    if (decile != last_decile_) {
      last_decile_ = decile;
      std::fprintf(out_, "%s %d/%d (%3.0f %%)  %.1f s elapsed  ETA %.1f s  retries %d\n",
                   label_.c_str(), done, total, frac * 100, elapsed, eta, retries);
    }
  }
  std::fflush(out_);
}

}  // namespace rnav
