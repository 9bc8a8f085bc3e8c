#include "estimators/diagnosis/bearing_reference_check.hpp"

#include "common/io/config.hpp"
#include "common/physics/bearing.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

namespace rnav {

namespace {

// Circular mean of angles [rad] and the circular sd sqrt(-2 ln R) [rad].
std::pair<double, double> circular(const std::vector<double>& a) {
  double c = 0, s = 0;
  for (double x : a) c += std::cos(x), s += std::sin(x);
  const double n = static_cast<double>(a.size());
  const double R = std::min(1.0, std::hypot(c, s) / n);
  return {std::atan2(s, c), R > 0 ? std::sqrt(-2 * std::log(R)) : M_PI};
}

std::string deg(double rad) { return short_num(rad / kDegToRad); }

// The checks (bearing_reference_check.hpp) without the note on --keep-references.
void check_references(const AzimuthData& data, const PlaneSeries& observer, const PlaneSeries& truth, double window_rad) {
  // the frames with detections and both references, and each one's reference bearing beta
  struct Frame {
    const BearingFrame* f;
    Eigen::Vector2d o;
    double beta;
  };
  std::vector<Frame> fr;
  for (const BearingFrame& f : data.frames) {
    Eigen::Vector2d po, pt;
    if (f.bearings_rad.empty() || !observer.at(f.t_s, po) || !truth.at(f.t_s, pt)) continue;
    fr.push_back({&f, po, bearing_rad(pt - po)});
  }
  if (static_cast<int>(fr.size()) < kRefMinFrames) return;  // the diagnosis's own count says so
  const int n = static_cast<int>(fr.size());
  // A predicted bearing per frame (false: none there) scored by the fraction of frames with a
  // detection within the window of it, those detections' median |r| (how tightly they fit) and
  // the median of min(|r|, window) over all frames.
  struct Fit {
    double fraction = 0, tight = INFINITY;
    double capped = INFINITY;  ///< median over frames of min(|r|, window): the shift's criterion
  };
  auto score = [&](const std::function<bool(const Frame&, double&)>& predicted) {
    std::vector<double> in, capped;
    for (const Frame& x : fr) {
      double p = 0;
      if (!predicted(x, p)) continue;
      const double e = std::abs(nearest_wrapped(x.f->bearings_rad, p));
      capped.push_back(std::min(e, window_rad));
      if (e <= window_rad) in.push_back(e);
    }
    Fit f;
    if (static_cast<int>(capped.size()) < kRefMinFrames) return f;
    f.fraction = static_cast<double>(in.size()) / static_cast<double>(capped.size());
    if (!in.empty()) f.tight = median(in);
    f.capped = median(capped);
    return f;
  };
  auto shifted = [&](double d) {
    return [&, d](const Frame& x, double& p) {
      Eigen::Vector2d pt;
      if (!truth.at(x.f->t_s + d, pt)) return false;
      p = bearing_rad(pt - x.o);
      return true;
    };
  };
  auto turned = [](double c, bool mirror) {
    return [c, mirror](const Frame& x, double& p) { return p = mirror ? c - x.beta : x.beta + c, true; };
  };
  const Fit f0 = score(shifted(0));
  // chance: the median over kChanceTurns turns of the reference bearing (what the frames' other
  // detections, clutter, give a reference that has nothing to do with them; a median, so that a
  // reciprocal turn of 180 deg does not count)
  std::vector<double> turns;
  for (int k = 1; k <= kChanceTurns; ++k) turns.push_back(score(turned(2 * M_PI * k / (kChanceTurns + 1), false)).fraction);
  const double chance = median(turns);
  const double se = std::sqrt(std::max(chance * (1 - chance), 1.0 / n) / n);
  const bool above_chance = f0.fraction - chance > kRefChanceZ * se;
  // the best shift of the target's reference: the least capped median over every shift that
  // leaves the reference over some frames (coarse, then fine about the best)
  const double d_lo = truth.t_first() - fr.back().f->t_s, d_hi = truth.t_last() - fr.front().f->t_s;
  double best_d = 0;
  Fit best = f0;
  auto scan = [&](double lo, double hi) {
    for (int k = 0; k <= kRefShiftSteps; ++k) {
      const double d = lo + (hi - lo) * k / kRefShiftSteps;
      const Fit f = score(shifted(d));
      if (f.capped < best.capped) best = f, best_d = d;
    }
  };
  scan(d_lo, d_hi);
  const double step = (d_hi - d_lo) / kRefShiftSteps;
  scan(best_d - 2 * step, best_d + 2 * step);
  const std::string seen = " (as stamped " + std::to_string(static_cast<int>(std::lround(f0.fraction * n))) + " of " +
                           std::to_string(n) + " frames have a detection within " + deg(window_rad) +
                           " deg of the bearing from observer.csv to truth.csv's target; " + short_num(100 * chance) +
                           " % would by chance)";
  // a shift named: beyond a clock, fitting most frames tightly (within a third of the window)
  // where the stamped reference's fits are kRefLooseFactor times looser (coincidences of a wrong
  // reference, not the target's detections)
  if (std::abs(best_d) > kRefMaxClockS && best.fraction >= kRefShiftFraction && best.capped <= window_rad / 3 &&
      !(f0.tight <= kRefLooseFactor * best.tight)) {
    char b[640];
    std::snprintf(b, sizeof b,
                  "truth.csv's time stamps look %+.1f s off bearings.csv's and observer.csv's: with the target's reference "
                  "taken %.1f s %s, %.0f %% of the frames have a detection within %s deg of it, a median %s deg from it "
                  "(as stamped %.0f %%, %s deg): one time scale for every file; or the sensor sees another object that "
                  "follows the target's path",
                  best_d, std::abs(best_d), best_d > 0 ? "later" : "earlier", 100 * best.fraction, deg(window_rad).c_str(),
                  deg(best.tight).c_str(),
                  100 * f0.fraction, std::isfinite(f0.tight) ? deg(f0.tight).c_str() : "-");
    throw ConfigError(b);
  }
  if (above_chance) return;
  // the references do not fit: the likeliest cause
  auto explains = [&](const Fit& f) { return f.fraction - chance >= kRefShiftFraction * (1 - chance) && f.capped <= window_rad / 3; };
  if (explains(score(turned(M_PI, false))))
    throw ConfigError("bearings.csv bearing_deg looks like the reciprocal bearing, from the target to the observer: its "
                      "detections lie 180 deg from the bearing to the target" + seen);
  std::vector<double> sum, own, refs;
  for (const Frame& x : fr) {
    const double b = x.f->bearings_rad.front();
    sum.push_back(b + x.beta), own.push_back(b), refs.push_back(x.beta);
  }
  const double c = circular(sum).first;
  if (explains(score(turned(c, true))))
    throw ConfigError("bearings.csv bearing_deg looks mirrored, counter-clockwise: its detections follow " + deg(c) +
                      " deg minus the bearing to the target (from east, counter-clockwise, where that is 90 deg)" + seen);
  const double own_sd = circular(own).second, ref_sd = circular(refs).second;
  if (own_sd < kRefFrozenSpreadDeg * kDegToRad && ref_sd > kRefMinSpreadDeg * kDegToRad)
    throw ConfigError("bearings.csv bearing_deg does not move: its detections spread " + deg(own_sd) +
                      " deg (circular sd) while the bearing to the target spreads " + deg(ref_sd) +
                      " deg: a frozen sensor or a repeated value" + seen);
  std::vector<double> dist;
  for (const Frame& x : fr) {
    Eigen::Vector2d pt;
    truth.at(x.f->t_s, pt);
    dist.push_back((pt - x.o).norm());
  }
  throw ConfigError("bearings.csv's detections do not follow the bearing from observer.csv to truth.csv's target, nor does "
                    "a time shift of truth.csv (" + short_num(d_lo) + " to " + short_num(d_hi) + " s) make them; the target lies "
                    "a median " + short_num(median(dist) / 1000) + " km from the observer: the references may be another "
                    "place's or another time's, or the sensor does not see the target" + seen);
}

}  // namespace

void check_bearing_references(const AzimuthData& data, const PlaneSeries& observer, const PlaneSeries& truth, double window_rad) {
  try {
    check_references(data, observer, truth, window_rad);
  } catch (const ConfigError& e) {
    throw ConfigError(std::string(e.what()) + " (--keep-references diagnoses it as it is)");
  }
}

}  // namespace rnav
