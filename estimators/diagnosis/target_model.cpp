#include "target_model.hpp"

#include "config.hpp"
#include "plane_series.hpp"
#include "stats.hpp"

#include <cmath>
#include <memory>

namespace rnav {

namespace {
// RMS about the least-squares straight line, the larger over the two axes [m].
double line_rms(const std::vector<std::pair<double, Eigen::Vector2d>>& s) {
  const auto n = static_cast<Eigen::Index>(s.size());
  Eigen::MatrixXd A(n, 2);
  Eigen::MatrixXd Y(n, 2);
  const double t0 = s.front().first;
  for (Eigen::Index i = 0; i < n; ++i) {
    A(i, 0) = 1, A(i, 1) = s[static_cast<std::size_t>(i)].first - t0;
    Y.row(i) = s[static_cast<std::size_t>(i)].second.transpose();
  }
  const Eigen::MatrixXd R = Y - A * A.colPivHouseholderQr().solve(Y);
  return std::sqrt(R.colwise().squaredNorm().maxCoeff() / static_cast<double>(n));
}
}  // namespace

TargetModelResult test_target_model(const std::map<std::string, std::vector<GeoSample>>& truth,
                                    const LocalLevelFrame& F, const TargetModelOptions& o) {
  if (!(o.min_spacing_s > 0) || !(o.nominal_sigma_m > 0) || !(o.resolution_m > 0) || o.grid < 2 || o.max_maneuvers < 1)
    throw ConfigError("target model: min_spacing_s, nominal_sigma_m, resolution_m > 0, grid >= 2, max_maneuvers >= 1");
  TargetModelResult res;
  Problem p;
  std::vector<std::string> names;
  struct Row {
    int target;
    int axis;
    double t;
  };
  auto rows = std::make_shared<std::vector<Row>>();
  std::vector<std::pair<double, double>> spans;
  for (const auto& [name, v] : truth) {
    std::vector<std::pair<double, Eigen::Vector2d>> s;
    for (const auto& g : v) {
      if (!s.empty() && g.t_s - s.back().first < o.min_spacing_s) continue;
      const Eigen::Vector3d q = F.from_geodetic(g.g);
      s.push_back({g.t_s, Eigen::Vector2d(q.x(), q.z())});
    }
    if (s.size() < 20) continue;
    if (line_rms(s) < o.resolution_m) {
      res.notes.push_back(name + ": the reference track is constant velocity to " + short_num(o.resolution_m) +
                          " m RMS (exact to its written precision): not searched for manoeuvres");
      continue;
    }
    const int ti = static_cast<int>(names.size());
    names.push_back(name);
    spans.push_back({s.front().first, s.back().first});
    for (int axis = 0; axis < 2; ++axis) {
      p.channels.push_back({name + (axis == 0 ? ":north" : ":east"), "", name, "m", o.nominal_sigma_m});
      for (const auto& [t, q] : s) {
        p.channel.push_back(2 * ti + axis);
        p.t_s.push_back(t);
        p.y.push_back(q(axis));
        p.estimation.push_back(t < s.front().first + 0.6 * (s.back().first - s.front().first));
        rows->push_back({ti, axis, t});
      }
    }
  }
  if (names.empty()) return res;
  const auto n = static_cast<Eigen::Index>(p.y.size());
  // nuisance: per target and axis, position and velocity about the span's middle
  p.nuisance = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(4 * names.size()));
  for (Eigen::Index i = 0; i < n; ++i) {
    const Row& r = (*rows)[static_cast<std::size_t>(i)];
    const auto& sp = spans[static_cast<std::size_t>(r.target)];
    const Eigen::Index c = 4 * r.target + 2 * r.axis;
    p.nuisance(i, c) = 1;
    p.nuisance(i, c + 1) = r.t - 0.5 * (sp.first + sp.second);
  }
  for (std::size_t ti = 0; ti < names.size(); ++ti) {
    p.nuisance_names.insert(p.nuisance_names.end(), {names[ti] + " north_m", names[ti] + " north_mps", names[ti] + " east_m",
                                                     names[ti] + " east_mps"});
    std::vector<double> grid;
    const auto& sp = spans[ti];
    for (int k = 0; k < o.grid; ++k) grid.push_back(sp.first + (sp.second - sp.first) * (0.1 + 0.8 * k / (o.grid - 1)));
    const int tgt = static_cast<int>(ti);
    // p(t) += dv (t - tau)+ on each axis
    auto columns = [rows, grid, tgt, n](std::size_t v) {
      Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 2);
      for (Eigen::Index i = 0; i < n; ++i) {
        const Row& r = (*rows)[static_cast<std::size_t>(i)];
        if (r.target == tgt && r.t > grid[v]) C(i, r.axis) = r.t - grid[v];
      }
      return C;
    };
    for (int m = 0; m < o.max_maneuvers; ++m)
      p.catalogue.push_back({"target_maneuver", {"", names[ti]}, {"dv_north_mps", "dv_east_mps"},
                             "a change of the target's velocity at one time", "t_s", grid, columns});
  }
  SearchOptions so = o.search;
  so.max_effects = o.max_maneuvers * static_cast<int>(names.size());
  const SearchResult r = search_effects(p, so);
  res.maneuvers = r.effects;
  for (std::size_t c = 0; c < r.noise.size(); ++c) {
    const auto& nf = r.noise[c].fit;
    res.notes.push_back(p.channels[c].name + " about the CV track with its manoeuvres: " + nf.params.kind() + " sigma " +
                        short_num(std::sqrt(nf.params.s2)) + " m" +
                        (nf.correlated ? ", tau " + short_num(nf.params.tau_s) + " s" : std::string()));
  }
  return res;
}

}  // namespace rnav
