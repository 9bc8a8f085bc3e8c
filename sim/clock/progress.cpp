#include "sim/clock/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace rnav {

namespace {
constexpr double kMinRedrawS = 0.1;  // [s wall] between in-place redraws within a realization
}  // namespace

ProgressBar::ProgressBar(std::string label) : ProgressBar(std::move(label), stderr, isatty(2) != 0) {}

ProgressBar::ProgressBar(std::string label, std::FILE* out, bool redraw)
    : label_(std::move(label)), out_(out), redraw_(redraw) {}

void ProgressBar::update(int done, int total, int retries, double now_s) {
  update(static_cast<double>(done), total, retries, now_s, "");
}

void ProgressBar::update(double done, int total, int retries, double now_s, const std::string& detail) {
  if (finished_) return;
  if (start_s_ < 0) start_s_ = now_s;
  // a bar redrawn inside a realization (detail given) at most every kMinRedrawS
  if (redraw_ && !detail.empty() && done < total && last_draw_s_ >= 0 && now_s - last_draw_s_ < kMinRedrawS) return;
  last_draw_s_ = now_s;
  const double elapsed = now_s - start_s_;
  const double frac = total > 0 ? std::min(1.0, done / total) : 1.0;
  // ETA = elapsed (total - done) / done; unknown before anything is done
  char eta[32] = "unknown";
  if (done > 0) std::snprintf(eta, sizeof eta, "%.1f s", elapsed * (total - done) / done);
  char count[64];
  if (done == std::floor(done)) std::snprintf(count, sizeof count, "%d/%d", static_cast<int>(done), total);
  else std::snprintf(count, sizeof count, "%.2f/%d", done, total);
  const std::string more = detail.empty() ? "" : "  " + detail;
  finished_ = done >= total;
  if (redraw_) {
    const int width = 30, fill = static_cast<int>(frac * width);
    std::fprintf(out_, "\r%s [%.*s%*s] %s%s  %.1f s elapsed  ETA %s  retries %d   ", label_.c_str(), fill,
                 "##############################", width - fill, "", count, more.c_str(), elapsed, eta, retries);
    if (finished_) std::fprintf(out_, "\n");
  } else {
    const int decile = static_cast<int>(frac * 10);
    if (decile != last_decile_) {
      last_decile_ = decile;
      std::fprintf(out_, "%s %s (%3.0f %%)%s  %.1f s elapsed  ETA %s  retries %d\n", label_.c_str(), count, frac * 100,
                   more.c_str(), elapsed, eta, retries);
    }
  }
  std::fflush(out_);
}

}  // namespace rnav
