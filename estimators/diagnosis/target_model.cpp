#include "estimators/diagnosis/target_model.hpp"

#include "estimators/model_id/parallel_for.hpp"

#include "common/io/config.hpp"
#include "estimators/diagnosis/plane_series.hpp"
#include "estimators/model_id/stats.hpp"

#include <cmath>
#include <memory>
#include <stdexcept>

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

namespace {

using Track = std::vector<std::pair<double, Eigen::Vector2d>>;  // (t_s, (north, east) [m])

// One target's problem: channels "<target>:north" and "<target>:east", nuisance position and
// velocity per axis about the span's middle, max_maneuvers target_maneuver entries.
Problem target_problem(const std::string& name, const Track& s, const TargetModelOptions& o) {
  Problem p;
  const double t_mid = 0.5 * (s.front().first + s.back().first), t_est = s.front().first + 0.6 * (s.back().first - s.front().first);
  auto t_s = std::make_shared<std::vector<double>>();
  auto axis_of = std::make_shared<std::vector<int>>();
  for (int axis = 0; axis < 2; ++axis) {
    p.channels.push_back({name + (axis == 0 ? ":north" : ":east"), "", name, "m", o.nominal_sigma_m});
    for (const auto& [t, q] : s) {
      p.channel.push_back(axis);
      p.t_s.push_back(t);
      p.y.push_back(q(axis));
      p.estimation.push_back(t < t_est);
      t_s->push_back(t);
      axis_of->push_back(axis);
    }
  }
  const auto n = static_cast<Eigen::Index>(p.y.size());
  p.nuisance = Eigen::MatrixXd::Zero(n, 4);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    p.nuisance(i, 2 * (*axis_of)[k]) = 1;
    p.nuisance(i, 2 * (*axis_of)[k] + 1) = (*t_s)[k] - t_mid;
  }
  p.nuisance_names = {name + " north_m", name + " north_mps", name + " east_m", name + " east_mps"};
  std::vector<double> grid;
  const double t0 = s.front().first, span = s.back().first - s.front().first;
  for (int k = 0; k < o.grid; ++k) grid.push_back(t0 + span * (0.1 + 0.8 * k / (o.grid - 1)));
  // p(t) += dv (t - tau)+ on each axis
  auto columns = [t_s, axis_of, grid, n](std::size_t v) {
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 2);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if ((*t_s)[k] > grid[v]) C(i, (*axis_of)[k]) = (*t_s)[k] - grid[v];
    }
    return C;
  };
  for (int m = 0; m < o.max_maneuvers; ++m)
    p.catalogue.push_back({"target_maneuver", {"", name}, {"dv_north_mps", "dv_east_mps"},
                           "a change of the target's velocity at one time", "t_s", grid, columns});
  return p;
}

}  // namespace

// Targets share no parameter, so each track is searched alone (on `threads` threads), with alpha
// split over the family of all the targets together (SearchOptions::family_size): the same
// tests at the same levels as one joint search, whose dense algebra grew with the square of the
// number of targets (40 AIS tracks of ten minutes: 28 s of a 41 s diagnosis; alone, a few
// seconds). The joint search there also named manoeuvres on only the first 3 of the 12 turning
// tracks (8 in all); alone, on all 12 (35).
TargetModelResult test_target_model(const std::map<std::string, std::vector<GeoSample>>& truth,
                                    const LocalLevelFrame& F, const TargetModelOptions& o) {
  if (!(o.min_spacing_s > 0) || !(o.nominal_sigma_m > 0) || !(o.resolution_m > 0) || o.grid < 2 || o.max_maneuvers < 1 ||
      o.threads < 1)
    throw ConfigError(
        "target model: min_spacing_s, nominal_sigma_m, resolution_m > 0, grid >= 2, max_maneuvers >= 1, threads >= 1");
  TargetModelResult res;
  std::vector<std::pair<std::string, Track>> searched;
  for (const auto& [name, v] : truth) {
    Track s;
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
    searched.push_back({name, std::move(s)});
  }
  if (searched.empty()) return res;
  SearchOptions so = o.search;
  so.progress = nullptr;  // one line per target instead (below)
  so.threads = 1;         // the tracks are searched at once instead
  so.max_effects = o.max_maneuvers;
  // the family: every target's entries and three noise tests on each of its two channels
  so.family_size = static_cast<double>(searched.size()) * (o.max_maneuvers + 3 * 2);
  std::vector<SearchResult> out(searched.size());
  parallel_for(searched.size(), o.threads, [&](std::size_t i) {
    try {
      if (o.search.progress)
        o.search.progress("reference track of target " + searched[i].first + " (" + std::to_string(i + 1) + " of " +
                          std::to_string(searched.size()) + ") searched for manoeuvres");
      out[i] = search_effects(target_problem(searched[i].first, searched[i].second, o), so);
    } catch (const std::exception& e) {
      throw std::runtime_error("target model of " + searched[i].first + ": " + e.what());
    }
  });
  for (std::size_t i = 0; i < searched.size(); ++i) {
    const SearchResult& r = out[i];
    res.maneuvers.insert(res.maneuvers.end(), r.effects.begin(), r.effects.end());
    for (std::size_t c = 0; c < r.noise.size(); ++c) {
      const auto& nf = r.noise[c].fit;
      res.notes.push_back(searched[i].first + (c == 0 ? ":north" : ":east") + std::string(" about the CV track with its manoeuvres: ") +
                          nf.params.kind() + " sigma " + short_num(std::sqrt(nf.params.s2)) + " m" +
                          (nf.correlated ? ", tau " + short_num(nf.params.tau_s) + " s" : std::string()));
    }
  }
  return res;
}

}  // namespace rnav
