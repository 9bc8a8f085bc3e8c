#include "uav_track.hpp"

#include "atomic_file.hpp"

#include <set>
#include <stdexcept>

namespace rnav {

namespace {

std::string g9(double x) { return significant(x, 9); }

}  // namespace

void UavTrack::add_object(std::int64_t utime, const tma::Vec4& x) {
  Frame& f = frames_[utime];
  f.has_object = true;
  f.object = x;
}

void UavTrack::add_uav(std::int64_t utime, const Eigen::Vector2d& p) {
  Frame& f = frames_[utime];
  f.has_uav = true;
  f.uav = p;
}

void UavTrack::add_bearing(std::int64_t utime, double bearing_rad) {
  Frame& f = frames_[utime];
  if (f.n_bearings++ == 0) f.bearing_rad = bearing_rad;
}

void UavTrack::add_estimate(std::int64_t utime, const std::string& estimator, const tma::Vec4& x,
                            const tma::Mat4& P) {
  Estimate e;
  e.x = x;
  e.P_nn = P(0, 0);
  e.P_ne = 0.5 * (P(0, 1) + P(1, 0));
  e.P_ee = P(1, 1);
  if (!frames_[utime].est.emplace(estimator, e).second)
    throw std::runtime_error("UAV_TMA: two estimates of '" + estimator + "' at utime " + std::to_string(utime));
}

std::string UavTrack::csv(std::int64_t epoch_utime, long realization) const {
  std::set<std::string> names;
  for (const auto& [t, f] : frames_)
    for (const auto& [name, e] : f.est) names.insert(name);
  std::string out =
      "realization,t_s,uav_north_m,uav_east_m,object_north_m,object_east_m,object_v_north_mps,object_v_east_mps,"
      "n_bearings,bearing_rad";
  for (const auto& n : names)
    out += "," + n + "_north_m," + n + "_east_m," + n + "_v_north_mps," + n + "_v_east_mps," + n + "_P_nn_m2," + n +
           "_P_ne_m2," + n + "_P_ee_m2";
  out += "\n";
  for (const auto& [t, f] : frames_) {
    if (!f.has_object)
      throw std::runtime_error("track.csv: no TRUTH_TARGET state at utime " + std::to_string(t) +
                               " (a frame of TRUTH_UAV, UAV_BEARING or UAV_TMA)");
    if (!f.has_uav)
      throw std::runtime_error("track.csv: no TRUTH_UAV state at utime " + std::to_string(t) +
                               " (TRUTH_TARGET has one)");
    out += std::to_string(realization) + "," + fixed((t - epoch_utime) * 1e-6, 6);
    out += "," + g9(f.uav.x()) + "," + g9(f.uav.y());
    for (int i = 0; i < 4; ++i) out += "," + g9(f.object[i]);
    out += "," + std::to_string(f.n_bearings) + "," + g9(f.bearing_rad);
    for (const auto& n : names) {
      const auto it = f.est.find(n);
      if (it == f.est.end()) {
        out += ",nan,nan,nan,nan,nan,nan,nan";
        continue;
      }
      const Estimate& e = it->second;
      for (int i = 0; i < 4; ++i) out += "," + g9(e.x[i]);
      out += "," + g9(e.P_nn) + "," + g9(e.P_ne) + "," + g9(e.P_ee);
    }
    out += "\n";
  }
  return out;
}

}  // namespace rnav
