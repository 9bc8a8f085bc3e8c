// Progress bar with ETA on stderr (a bar redrawn in place on a terminal, a line per 10 %
// otherwise).
#pragma once

#include <string>

namespace rnav {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  /// done of total finished at wall time now_s (monotonic); `retries` so far.
  void update(int done, int total, int retries, double now_s);

 private:
  std::string label_;
  bool tty_;
  double start_s_ = -1;
  int last_decile_ = -1;
};

}  // namespace rnav
