#include "estimators/diagnosis/rotation_scans.hpp"

#include "estimators/model_id/stats.hpp"

#include <cmath>

namespace rnav {

namespace {

constexpr double kTwoPi = 2 * M_PI;
constexpr double kRefineLo = 0.3, kRefineHi = 0.7;  // refining pairs' spacing, in coarse periods
constexpr int kRefinePartners = 3;                  // partners per detection in the refining step
constexpr double kAgreeTolerance = 0.05;            // a pair agrees within 5 % of the median rate
constexpr double kMinAgreeing = 0.5;                // a rotating sensor: at least half of the pairs agree

double mod_two_pi(double x) {
  x = std::fmod(x, kTwoPi);
  return x < 0 ? x + kTwoPi : x;
}

// The median rate of pairs spaced [lo, hi] x period apart, and the fraction agreeing with it.
RotationEstimate refine(const std::vector<double>& t, const std::vector<double>& b, int dir, double period) {
  std::vector<double> w;
  const std::size_t n = t.size();
  for (std::size_t i = 0; i < n; ++i) {
    int taken = 0;
    for (std::size_t j = i + 1; j < n && taken < kRefinePartners; ++j) {
      const double dt = t[j] - t[i];
      if (dt > kRefineHi * period) break;
      if (dt < kRefineLo * period) continue;
      w.push_back(mod_two_pi(dir * (b[j] - b[i])) / dt);
      ++taken;
    }
  }
  RotationEstimate r;
  r.pairs = static_cast<int>(w.size());
  if (w.size() < 3) return r;
  const double om = median(w);
  if (!(om > 0) || !std::isfinite(om)) return r;
  int agree = 0;
  for (double x : w) agree += std::abs(x / om - 1) < kAgreeTolerance;
  r.agreeing_fraction = static_cast<double>(agree) / static_cast<double>(w.size());
  r.period_s = kTwoPi / om;
  r.direction = dir;
  return r;
}

}  // namespace

RotationEstimate rotation_period(const std::vector<double>& t, const std::vector<double>& b) {
  RotationEstimate best;
  if (static_cast<int>(t.size()) < kMinRotationDetections || t.size() != b.size()) return best;
  for (int dir : {1, -1}) {
    std::vector<double> w;  // coarse: consecutive detections
    for (std::size_t i = 0; i + 1 < t.size(); ++i)
      if (t[i + 1] > t[i]) w.push_back(mod_two_pi(dir * (b[i + 1] - b[i])) / (t[i + 1] - t[i]));
    if (w.size() < 3) continue;
    const double om0 = median(w);
    if (!(om0 > 0) || !std::isfinite(om0)) continue;
    RotationEstimate r = refine(t, b, dir, kTwoPi / om0);
    if (r.period_s > 0) r = refine(t, b, dir, r.period_s);  // again about the refined period
    if (r.agreeing_fraction > best.agreeing_fraction) best = r;
  }
  if (!(best.agreeing_fraction >= kMinAgreeing)) return {0, 0, best.agreeing_fraction, best.pairs};
  return best;
}

}  // namespace rnav
