#include "sim/scene/recorded_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav::scene {

bool Coverage::covers(double bearing_rad, double range_m) const {
  double a = std::fmod(bearing_rad - bearing_lo_rad, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  const bool in_arc = a <= bearing_span_rad;
  return in_arc && (std::isnan(range_m) || (range_m >= range_lo_m && range_m <= range_hi_m));
}

namespace {
void check_track(const std::vector<GeoSample>& tr, const std::string& what) {
  if (tr.empty()) throw std::invalid_argument("recorded scene: " + what + " has no samples");
  for (std::size_t i = 0; i < tr.size(); ++i) {
    if (!std::isfinite(tr[i].t_s) || !std::isfinite(tr[i].g.lat_deg) || !std::isfinite(tr[i].g.lon_deg))
      throw std::invalid_argument("recorded scene: " + what + " sample " + std::to_string(i) + " is not finite");
    if (i > 0 && !(tr[i].t_s > tr[i - 1].t_s))
      throw std::invalid_argument("recorded scene: " + what + " times do not increase at sample " + std::to_string(i));
  }
}
}  // namespace

void RecordedScene::check() const {
  check_track(observer, "the observer's track");
  if (!observer_heading_deg.empty() && observer_heading_deg.size() != observer.size())
    throw std::invalid_argument("recorded scene: the observer's heading has " + std::to_string(observer_heading_deg.size()) +
                                " samples, its track " + std::to_string(observer.size()));
  for (const auto& [t, tr] : targets) check_track(tr, "target " + t + "'s track");
  if (!(reference_max_gap_s > 0)) throw std::invalid_argument("recorded scene: reference_max_gap_s must be > 0");
  if (!(min_speed_mps >= 0)) throw std::invalid_argument("recorded scene: min_speed_mps must be >= 0");
  for (const auto& s : sensors) {
    const std::string w = "recorded scene: sensor " + s.name + ": ";
    if (s.scan_times_s.empty()) throw std::invalid_argument(w + "no scans");
    for (std::size_t i = 1; i < s.scan_times_s.size(); ++i)
      if (!(s.scan_times_s[i] > s.scan_times_s[i - 1])) throw std::invalid_argument(w + "scan times do not increase at scan " + std::to_string(i));
    if (!(s.scan_period_s > 0)) throw std::invalid_argument(w + "scan_period_s must be > 0");
    const Rotation& r = s.rotation;
    if (!(r.period_s >= 0) || !std::isfinite(r.period_s) || (r.direction != 1 && r.direction != -1) || !std::isfinite(r.t0_s) ||
        !(std::abs(r.b0_rad) <= M_PI))
      throw std::invalid_argument(w + "rotation out of range (period_s finite and >= 0, direction +1 or -1, t0_s finite, b0_rad in [-pi, pi])");
    const Coverage& c = s.coverage;
    if (!(c.bearing_span_rad > 0 && c.bearing_span_rad <= 2 * M_PI) || !(c.range_lo_m >= 0 && c.range_hi_m > c.range_lo_m))
      throw std::invalid_argument(w + "coverage out of range (span in (0, 2 pi], 0 <= range_lo < range_hi)");
    for (const auto& [t, p] : s.p_detect)
      if (!(p >= 0 && p <= 1)) throw std::invalid_argument(w + "detection probability of target " + t + " not in [0, 1]");
    if (!(s.clutter_per_scan >= 0) || !std::isfinite(s.clutter_per_scan)) throw std::invalid_argument(w + "clutter_per_scan must be finite and >= 0");
    if (!s.replay_clutter && s.clutter_per_scan > 0 && s.clutter.empty()) throw std::invalid_argument(w + "clutter rate > 0 but no clutter to draw from");
    for (std::size_t i = 1; i < s.clutter.size(); ++i)
      if (s.clutter[i].t_s < s.clutter[i - 1].t_s) throw std::invalid_argument(w + "clutter times decrease at return " + std::to_string(i));
  }
}

double RecordedScene::start_s() const {
  double t = observer.empty() ? INFINITY : observer.front().t_s;
  for (const auto& [_, tr] : targets)
    if (!tr.empty()) t = std::min(t, tr.front().t_s);
  for (const auto& s : sensors)
    if (!s.scan_times_s.empty()) t = std::min(t, s.scan_times_s.front());
  if (!std::isfinite(t)) throw std::invalid_argument("recorded scene: no recorded time (no track, no scan)");
  return std::floor(t);
}

double RecordedScene::duration_s() const {
  double t = observer.empty() ? -INFINITY : observer.back().t_s;
  for (const auto& [_, tr] : targets)
    if (!tr.empty()) t = std::max(t, tr.back().t_s);
  for (const auto& s : sensors)
    if (!s.scan_times_s.empty()) t = std::max(t, s.scan_times_s.back());
  return t - start_s();
}

// t - start is exact for the recordings' times (Sterbenz: start <= t <= 2 start for Unix
// seconds), so a time stamp with microsecond digits comes back to the same digits.
std::int64_t SceneTime::utime(double t) const { return epoch_utime + std::llround((t - start_s) * 1e6); }
double SceneTime::t_s(std::int64_t u) const { return start_s + static_cast<double>(u - epoch_utime) * 1e-6; }

}  // namespace rnav::scene
