// Progress bar with ETA: a bar redrawn in place ('\r') when the output is a terminal, otherwise
// a plain line at 0 % and at every further 10 % (logs and pipes get no control characters).
#pragma once

#include <cstdio>
#include <string>

namespace rnav {

class ProgressBar {
 public:
  /// On stderr, redrawn in place only if stderr is a terminal (isatty).
  explicit ProgressBar(std::string label);
  /// On `out`; `redraw`: a bar redrawn in place, else a line per 10 %.
  ProgressBar(std::string label, std::FILE* out, bool redraw);
  /// done of total finished at wall time now_s [s] (monotonic); `retries` so far.
  void update(int done, int total, int retries, double now_s);
  /// The same with done fractional (a realization partly run) and a detail after the count
  /// (e.g. "sim 12.0/50.0 s"). Before anything is done the ETA is unknown, never 0.
  void update(double done, int total, int retries, double now_s, const std::string& detail);

 private:
  std::string label_;
  std::FILE* out_;
  bool redraw_;
  double start_s_ = -1;
  double last_draw_s_ = -1;
  int last_decile_ = -1;
  bool finished_ = false;
};

}  // namespace rnav
