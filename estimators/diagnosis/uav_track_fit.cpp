#include "estimators/diagnosis/uav_track_fit.hpp"

#include "common/physics/bearing.hpp"
#include "common/io/config.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace rnav {

double CvTrack::bearing(const TrackObs& x) const {
  return bearing_rad(at(x.t_s) - x.o_F);
}

Eigen::Vector4d CvTrack::jacobian(const TrackObs& x) const {
  // d beta/d p (bearing_jacobian); d p / d v = (t - t_ref).
  const Eigen::RowVector2d g = bearing_jacobian(at(x.t_s) - x.o_F);
  const double dt = x.t_s - t_ref_s;
  return {g(0), g(1), dt * g(0), dt * g(1)};
}

double CvTrack::bearing_rate(const TrackObs& x) const {
  return bearing_rate_radps(at(x.t_s) - x.o_F, v_F - x.vo_F);
}

std::vector<TrackObs> track_observations(const AzimuthData& data, const LocalLevelFrame& F) {
  const PlaneSeries observer(data.observer, F);
  std::vector<TrackObs> obs;
  const double h = 0.5;  // [s] half-span of the velocity's central difference
  for (const auto& fr : data.frames) {
    TrackObs x;
    Eigen::Vector2d a, b;
    if (fr.bearings_rad.empty() || !observer.at(fr.t_s, x.o_F) || !observer.at(fr.t_s - h, a) || !observer.at(fr.t_s + h, b)) continue;
    x.t_s = fr.t_s;
    x.vo_F = (b - a) / (2 * h);
    x.bearings_rad = fr.bearings_rad;
    obs.push_back(std::move(x));
  }
  return obs;
}

namespace {

// Pseudo-linear estimate from one detection per listed frame: rows
//   [sin b, -cos b, dt sin b, -dt cos b] theta = o_n sin b - o_e cos b.
bool pseudo_linear(const std::vector<TrackObs>& obs, const std::vector<std::pair<std::size_t, double>>& rows,
                   double t_ref, CvTrack& out) {
  Eigen::MatrixXd A(rows.size(), 4);
  Eigen::VectorXd y(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& x = obs[rows[i].first];
    const double s = std::sin(rows[i].second), c = std::cos(rows[i].second), dt = x.t_s - t_ref;
    A.row(static_cast<Eigen::Index>(i)) << s, -c, dt * s, -dt * c;
    y(static_cast<Eigen::Index>(i)) = x.o_F.x() * s - x.o_F.y() * c;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 4) return false;
  const Eigen::Vector4d th = qr.solve(y);
  if (!th.allFinite()) return false;
  out.t_ref_s = t_ref;
  out.p0_F = th.head<2>();
  out.v_F = th.tail<2>();
  return true;
}

// Nearest detection within the gate, or -1.
int nearest(const TrackObs& x, double predicted, double gate) {
  int best = -1;
  double bd = gate;
  for (std::size_t j = 0; j < x.bearings_rad.size(); ++j) {
    const double d = std::abs(wrap_pi(x.bearings_rad[j] - predicted));
    if (d <= bd) {
      bd = d;
      best = static_cast<int>(j);
    }
  }
  return best;
}

}  // namespace

TrackFit fit_cv_track(const std::vector<TrackObs>& obs, double t_begin, double t_end, const TrackFitOptions& o) {
  if (!(o.gate_deg > 0 && o.gate_deg <= 90)) throw ConfigError("track fit: gate_deg must be in (0, 90]");
  if (o.ransac_trials < 1) throw ConfigError("track fit: ransac_trials must be >= 1");
  std::vector<std::size_t> win;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (obs[i].t_s >= t_begin && obs[i].t_s <= t_end) win.push_back(i);
  if (win.size() < 10) throw ConfigError("track fit: fewer than 10 frames with detections in the fit window");
  const double gate = o.gate_deg * kDegToRad;
  const double t_ref = 0.5 * (obs[win.front()].t_s + obs[win.back()].t_s);

  // ---- RANSAC initialisation ----
  std::mt19937_64 rng(o.seed);
  std::uniform_int_distribution<std::size_t> pick(0, win.size() - 1);
  CvTrack best;
  int best_inl = -1;
  double best_ss = 0;
  for (int trial = 0; trial < o.ransac_trials; ++trial) {
    std::vector<std::pair<std::size_t, double>> rows;
    for (int k = 0; k < 4; ++k) {
      const auto& x = obs[win[pick(rng)]];
      std::uniform_int_distribution<std::size_t> pd(0, x.bearings_rad.size() - 1);
      rows.emplace_back(static_cast<std::size_t>(&x - obs.data()), x.bearings_rad[pd(rng)]);
    }
    CvTrack tr;
    if (!pseudo_linear(obs, rows, t_ref, tr)) continue;
    int inl = 0;
    double ss = 0;
    for (auto i : win) {
      const double b = tr.bearing(obs[i]);
      const int j = nearest(obs[i], b, gate);
      if (j < 0) continue;
      ++inl;
      const double r = wrap_pi(obs[i].bearings_rad[static_cast<std::size_t>(j)] - b);
      ss += r * r;
    }
    if (inl > best_inl || (inl == best_inl && ss < best_ss)) {
      best_inl = inl;
      best_ss = ss;
      best = tr;
    }
  }
  if (best_inl < 10)
    throw ConfigError("track fit: no constant-velocity track explains the bearings (best initial track "
                      "associates " + std::to_string(std::max(best_inl, 0)) + " frames)");

  // ---- alternate association and Gauss-Newton ----
  TrackFit f;
  f.track = best;
  std::vector<int> assoc(obs.size(), -1);
  for (int round = 0; round < 20; ++round) {
    std::vector<int> next(obs.size(), -1);
    for (auto i : win) next[i] = nearest(obs[i], f.track.bearing(obs[i]), gate);
    const bool same = next == assoc;
    assoc = next;
    std::vector<std::size_t> used;
    for (auto i : win)
      if (assoc[i] >= 0) used.push_back(i);
    if (used.size() < 10) throw ConfigError("track fit: fewer than 10 frames associate with the track");
    auto cost = [&](const CvTrack& tr) {
      double c = 0;
      for (auto i : used) {
        const double r = wrap_pi(obs[i].bearings_rad[static_cast<std::size_t>(assoc[i])] - tr.bearing(obs[i]));
        c += r * r;
      }
      return c;
    };
    Eigen::Matrix4d N;
    Eigen::Vector4d d;
    for (int it = 0; it < o.max_iterations; ++it) {
      N.setZero();
      Eigen::Vector4d g = Eigen::Vector4d::Zero();
      for (auto i : used) {
        const Eigen::Vector4d J = f.track.jacobian(obs[i]);
        const double r = wrap_pi(obs[i].bearings_rad[static_cast<std::size_t>(assoc[i])] - f.track.bearing(obs[i]));
        N += J * J.transpose();
        g += J * r;
      }
      // Equilibrate: position and velocity columns differ by the time span.
      for (int k = 0; k < 4; ++k) d(k) = N(k, k) > 0 ? 1.0 / std::sqrt(N(k, k)) : 1.0;
      const Eigen::Matrix4d Ns = d.asDiagonal() * N * d.asDiagonal();
      const Eigen::JacobiSVD<Eigen::Matrix4d> svd(Ns);
      f.condition = svd.singularValues()(0) / std::max(svd.singularValues()(3), 1e-300);
      if (f.condition > 1e12)
        throw ConfigError("track fit: the object's constant-velocity track is not observable from this "
                          "observer path (condition number " + short_num(f.condition) + ")");
      const Eigen::Vector4d step = d.asDiagonal() * Ns.ldlt().solve(d.asDiagonal() * g);
      const double c0 = cost(f.track);
      double lam = 1;
      CvTrack trial = f.track;
      for (int h = 0; h < 30; ++h, lam *= 0.5) {
        trial = f.track;
        trial.p0_F += lam * step.head<2>();
        trial.v_F += lam * step.tail<2>();
        if (cost(trial) <= c0) break;
      }
      f.track = trial;
      if (lam * step.head<2>().norm() < 1e-6 && lam * step.tail<2>().norm() < 1e-8) break;
    }
    const double ss = cost(f.track);
    f.n_associated = static_cast<int>(used.size());
    f.rms_rad = std::sqrt(ss / used.size());
    const double s2 = ss / std::max<double>(1, used.size() - 4);
    f.cov = s2 * d.asDiagonal() * (d.asDiagonal() * N * d.asDiagonal()).inverse() * d.asDiagonal();
    if (same) break;
  }
  f.associated = assoc;
  return f;
}

}  // namespace rnav
