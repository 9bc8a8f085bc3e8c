#include "loggers/uav_track.hpp"

#include "common/io/atomic_file.hpp"

#include <set>
#include <stdexcept>

namespace rnav {

namespace {

std::string g9(double x) { return significant(x, 9); }

// The columns before the estimators' groups, and each group's size.
constexpr std::size_t kFixedColumns = 10, kPerEstimator = 7;

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

std::vector<std::string> UavTrack::estimators() const {
  std::set<std::string> names;
  for (const auto& [t, f] : frames_)
    for (const auto& [name, e] : f.est) names.insert(name);
  return {names.begin(), names.end()};
}

std::vector<CsvColumnDoc> UavTrack::columns(const std::vector<std::string>& estimators) {
  const std::string in_F = " (local level frame F at the scenario origin)";
  std::vector<CsvColumnDoc> c{
      {"realization", "", "realization index (logger.track_realization)"},
      {"t_s", "s", "frame time since sim time 0 (runner.epoch_utime)"},
      {"uav_north_m", "m", "the UAV's true position north" + in_F},
      {"uav_east_m", "m", "the UAV's true position east" + in_F},
      {"object_north_m", "m", "the object's true position north" + in_F},
      {"object_east_m", "m", "the object's true position east" + in_F},
      {"object_v_north_mps", "m/s", "the object's true velocity north" + in_F},
      {"object_v_east_mps", "m/s", "the object's true velocity east" + in_F},
      {"n_bearings", "", "bearings measured at this frame"},
      {"bearing_rad", "rad", "the frame's first measured bearing, clockwise from north; nan when n_bearings = 0"}};
  for (const auto& n : estimators) {
    const std::string none = "; nan before its first estimate";
    c.push_back({n + "_north_m", "m", n + "'s estimate of the object's position north" + in_F + none});
    c.push_back({n + "_east_m", "m", n + "'s estimate of the object's position east" + none});
    c.push_back({n + "_v_north_mps", "m/s", n + "'s estimate of the object's velocity north" + none});
    c.push_back({n + "_v_east_mps", "m/s", n + "'s estimate of the object's velocity east" + none});
    c.push_back({n + "_P_nn_m2", "m^2", n + "'s position covariance, north-north" + none});
    c.push_back({n + "_P_ne_m2", "m^2", n + "'s position covariance, north-east (mean of its two off-diagonal terms)" + none});
    c.push_back({n + "_P_ee_m2", "m^2", n + "'s position covariance, east-east" + none});
  }
  return c;
}

std::vector<CsvColumnDoc> UavTrack::columns_of_header(const std::string& header, const std::string& what) {
  const std::vector<std::string> names = csv_header_names(header);
  std::vector<std::string> estimators;
  const std::string tail = "_north_m";
  for (std::size_t i = kFixedColumns; i < names.size(); i += kPerEstimator) {
    const std::string& n = names[i];
    if (n.size() > tail.size() && n.compare(n.size() - tail.size(), tail.size(), tail) == 0)
      estimators.push_back(n.substr(0, n.size() - tail.size()));
  }
  std::vector<CsvColumnDoc> c;
  try {
    c = columns(estimators);
    if (csv_header(c) != header.substr(0, header.find('\n') + 1)) c.clear();
  } catch (const std::invalid_argument&) {
    c.clear();
  }
  if (c.empty()) throw std::runtime_error(what + ": its header is not the one of a track.csv this build writes");
  return c;
}

std::string UavTrack::csv(std::int64_t epoch_utime, long realization) const {
  const std::vector<std::string> names = estimators();
  std::string out = csv_header(columns(names));
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
