#include "sim/target/target_motion.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rnav {

TargetMotion::TargetMotion(const TargetOptions& o, double step_s) : o_(o), step_s_(step_s) {}

TargetKinematics TargetMotion::at(double t_s) const {
  // Piecewise-constant (turn rate, acceleration) between the manoeuvre boundaries; within a
  // piece the course psi and speed s evolve as psi' = w, s' = a, and the position is
  // integrated with the exact solution for w = 0 and a midpoint rule for w != 0 on sub-steps.
  std::vector<double> cuts{0.0, t_s};
  for (const auto& m : o_.manoeuvres) {
    if (m[0] < t_s) cuts.push_back(m[0]);
    if (m[0] + m[1] < t_s) cuts.push_back(m[0] + m[1]);
  }
  std::sort(cuts.begin(), cuts.end());
  double psi = o_.heading_deg * kDegToRad, s = o_.speed_mps;
  Eigen::Vector2d p(o_.start_north_m, o_.start_east_m);
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double t0 = cuts[i], t1 = cuts[i + 1];
    if (t1 <= t0) continue;
    double w = 0, a = 0;
    for (const auto& m : o_.manoeuvres)
      if (t0 >= m[0] && t0 < m[0] + m[1]) {
        w += m[2] * kDegToRad;
        a += m[3];
      }
    if (w == 0) {
      // Straight: exact, p += (s h + a h^2 / 2) u, stopping when the speed reaches 0.
      double h = t1 - t0;
      if (a < 0 && s + a * h < 0) h = -s / a;
      p += (s * h + 0.5 * a * h * h) * Eigen::Vector2d(std::cos(psi), std::sin(psi));
      s = std::max(0.0, s + a * (t1 - t0));
      continue;
    }
    const int n = std::max(1, static_cast<int>(std::ceil((t1 - t0) / step_s_ * 10)));
    const double h = (t1 - t0) / n;
    for (int k = 0; k < n; ++k) {
      const double pm = psi + 0.5 * w * h, sm = std::max(0.0, s + 0.5 * a * h);
      p += h * sm * Eigen::Vector2d(std::cos(pm), std::sin(pm));
      psi += w * h;
      s = std::max(0.0, s + a * h);
    }
  }
  return {p, s * Eigen::Vector2d(std::cos(psi), std::sin(psi))};
}

}  // namespace rnav
