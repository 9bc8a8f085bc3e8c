#include "uav_diagnose.hpp"

#include "config.hpp"
#include "uav_track_fit.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace rnav {

namespace {

struct Ob {
  double t = 0, meas = 0;  ///< frame time [s], associated detection [rad]
  double r = 0;            ///< residual against the reference track [rad]
  double rate = 0;         ///< [rad/s] reference bearing rate
  double range = 0;        ///< [m] reference horizontal range
  Eigen::Vector4d J = Eigen::Vector4d::Zero();  ///< estimated mode: d bearing / d (p0, v) of the track
  std::size_t k = 0;       ///< estimated mode: index into the track observations
  bool outlier = false;
};

using Col = std::function<double(const Ob&)>;

struct Fit1 {
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov;
  double rss = 0, n = 0;
  bool ok = false;
};

// OLS of r on the given columns (no intercept: the nominal model has zero mean).
Fit1 ols(const std::vector<Ob>& obs, const std::vector<std::size_t>& idx, const std::vector<Col>& cols) {
  Fit1 f;
  const auto k = static_cast<Eigen::Index>(cols.size());
  Eigen::VectorXd y(idx.size());
  Eigen::MatrixXd X(idx.size(), k);
  for (std::size_t i = 0; i < idx.size(); ++i) {
    y(i) = obs[idx[i]].r;
    for (Eigen::Index j = 0; j < k; ++j) X(i, j) = cols[j](obs[idx[i]]);
  }
  f.n = static_cast<double>(idx.size());
  if (k == 0) {
    f.rss = y.squaredNorm();
    f.ok = true;
    return f;
  }
  Eigen::VectorXd d(k);
  for (Eigen::Index j = 0; j < k; ++j) d(j) = X.col(j).norm() > 0 ? 1.0 / X.col(j).norm() : 1.0;
  const Eigen::MatrixXd Xs = X * d.asDiagonal();
  Eigen::LDLT<Eigen::MatrixXd> ldlt(Xs.transpose() * Xs);
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-12) return f;
  f.beta = d.asDiagonal() * ldlt.solve(Xs.transpose() * y);
  f.rss = (y - X * f.beta).squaredNorm();
  const double s2 = f.rss / std::max(1.0, f.n - static_cast<double>(k));
  f.cov = s2 * d.asDiagonal() * ldlt.solve(Eigen::MatrixXd::Identity(k, k)) * d.asDiagonal();
  f.ok = true;
  return f;
}

// An effect of the catalogue: its columns, parameter names and (for scanned effects) the scan
// value (period or manoeuvre time).
struct Effect {
  std::string name;
  std::vector<Col> cols;
  std::vector<std::string> params;
  double scan_value = 0;
  double scan_size = 1;
};

double ramp(double t, double tau) { return t > tau ? t - tau : 0.0; }

// The extended track: the CV track plus the chosen manoeuvres (velocity changes dv at tau).
struct ExtTrack {
  CvTrack cv;
  std::vector<double> tau;
  std::vector<Eigen::Vector2d> dv;
  Eigen::Vector2d at(double t) const {
    Eigen::Vector2d p = cv.at(t);
    for (std::size_t m = 0; m < tau.size(); ++m) p += dv[m] * ramp(t, tau[m]);
    return p;
  }
};

// Residuals of the scored (out-of-sample) frames under the nominal and the extended model, and
// the extended model's residuals in the estimation window.
struct Scored {
  std::vector<double> t, r0, r1, est_r1;
};

// AR(1) coefficient per frame from the lag-1 correlation r_d of the first differences:
// for AR(1) noise r_d = (rho - 1) / 2, so rho = 1 + 2 r_d, clamped to [0, 0.99].
// Lag-1 correlation r_d of the first differences of r (0 without spread).
double diff_lag1(const std::vector<double>& r) {
  double num = 0, den = 0, prev = 0;
  for (std::size_t i = 1; i < r.size(); ++i) {
    const double d = r[i] - r[i - 1];
    den += d * d;
    if (i > 1) num += d * prev;
    prev = d;
  }
  return den > 0 ? num / den : 0.0;
}
double ar1_from_differences(const std::vector<double>& r) { return std::clamp(1 + 2 * diff_lag1(r), 0.0, 0.99); }

// Log-likelihood of residuals e at times t under zero-mean noise of marginal sigma s, white
// (tau = 0) or Gauss-Markov with correlation time tau: e_k | e_j ~ N(phi e_j, s^2 (1 - phi^2)),
// phi = exp(-(t_k - t_j) / tau), j the last frame within the gate (a frame beyond it, |e| >
// gate, is no sample of the noise process and does not condition the next); with probability
// p_out a frame is instead an outlier ~ N(0, s_out^2): the mixture (1 - p) N(m, v) + p N(0, s_out^2).
double ar1_loglik(const std::vector<double>& t, const std::vector<double>& e, double gate, double s, double tau,
                  double p_out = 0, double s_out = 1) {
  double ll = 0;
  auto pdf = [](double x, double m, double v) { return std::exp(-0.5 * (x - m) * (x - m) / v) / std::sqrt(2 * M_PI * v); };
  bool have_prev = false;
  double t_prev = 0, e_prev = 0;
  for (std::size_t k = 0; k < e.size(); ++k) {
    const double phi = (tau > 0 && have_prev) ? std::exp(-(t[k] - t_prev) / tau) : 0.0;
    const double m = phi * e_prev, v = s * s * (1 - phi * phi);
    if (p_out > 0)
      ll += std::log((1 - p_out) * pdf(e[k], m, v) + p_out * pdf(e[k], 0, s_out * s_out) + 1e-300);
    else
      ll += -0.5 * ((e[k] - m) * (e[k] - m) / v + std::log(2 * M_PI * v));
    if (std::abs(e[k]) <= gate) have_prev = true, t_prev = t[k], e_prev = e[k];
  }
  return ll;
}

// Gauss-Newton fit of the extended track (CV track + velocity changes at taus) plus the
// linear effect columns fx_cols to the frames e_obs (each with its associated detection), from
// the track `start`. res: the residuals of the last linearised step. False if it diverges.
bool fit_extended(const std::vector<Ob>& e_obs, const std::vector<TrackObs>& tobs, const CvTrack& start,
                  const std::vector<double>& taus, const std::vector<Col>& fx_cols, ExtTrack& tr,
                  Eigen::VectorXd& beta, std::vector<double>& res) {
  double s_fit = 0;
  tr = ExtTrack{};
  tr.cv = start;
  tr.tau = taus;
  tr.dv.assign(taus.size(), Eigen::Vector2d::Zero());
  const std::size_t nb = fx_cols.size();
  beta = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nb));
  const auto np = static_cast<Eigen::Index>(4 + 2 * tr.tau.size() + nb);
  for (int it = 0; it < 20; ++it) {
    Eigen::MatrixXd X(static_cast<Eigen::Index>(e_obs.size()), np);
    Eigen::VectorXd y(static_cast<Eigen::Index>(e_obs.size()));
    for (std::size_t i = 0; i < e_obs.size(); ++i) {
      const TrackObs& to = tobs[e_obs[i].k];
      const Eigen::Vector2d d = tr.at(to.t_s) - to.o_F;
      const double r2 = d.squaredNorm(), gn = -d.y() / r2, ge = d.x() / r2, dt = to.t_s - tr.cv.t_ref_s;
      double h = std::atan2(d.y(), d.x());
      for (std::size_t j = 0; j < nb; ++j) h += beta(static_cast<Eigen::Index>(j)) * fx_cols[j](e_obs[i]);
      const auto row = static_cast<Eigen::Index>(i);
      y(row) = wrap_pi(e_obs[i].meas - h);
      X(row, 0) = gn, X(row, 1) = ge, X(row, 2) = dt * gn, X(row, 3) = dt * ge;
      for (std::size_t m = 0; m < tr.tau.size(); ++m) {
        const double rm = ramp(to.t_s, tr.tau[m]);
        X(row, static_cast<Eigen::Index>(4 + 2 * m)) = rm * gn;
        X(row, static_cast<Eigen::Index>(5 + 2 * m)) = rm * ge;
      }
      for (std::size_t j = 0; j < nb; ++j) X(row, static_cast<Eigen::Index>(4 + 2 * tr.tau.size() + j)) = fx_cols[j](e_obs[i]);
    }
    Eigen::VectorXd dsc(np);
    for (Eigen::Index j = 0; j < np; ++j) dsc(j) = X.col(j).norm() > 0 ? 1.0 / X.col(j).norm() : 1.0;
    const Eigen::VectorXd step = dsc.asDiagonal() * (X * dsc.asDiagonal()).colPivHouseholderQr().solve(y);
    if (!step.allFinite()) return false;
    const Eigen::VectorXd e = y - X * step;
    res.assign(e.data(), e.data() + e.size());
    s_fit = std::sqrt(e.squaredNorm() / static_cast<double>(e_obs.size()));
    tr.cv.p0_F += step.segment<2>(0);
    tr.cv.v_F += step.segment<2>(2);
    for (std::size_t m = 0; m < tr.tau.size(); ++m) tr.dv[m] += step.segment<2>(static_cast<Eigen::Index>(4 + 2 * m));
    beta += step.tail(static_cast<Eigen::Index>(nb));
    if (step.head<2>().norm() < 1e-4) break;
  }
  return std::isfinite(s_fit) && s_fit > 0 && tr.cv.p0_F.allFinite();
}

}  // namespace

DiagnoseReport diagnose_uav(const AzimuthData& data, const UavDiagnoseOptions& o) {
  if (!(o.gate_deg > 0 && o.gate_deg <= 90)) throw ConfigError("diagnose uav: gate must be in (0, 90] deg");
  if (!(o.sigma_deg > 0)) throw ConfigError("diagnose uav: sigma must be > 0 deg");
  if (!(o.alpha > 0 && o.alpha < 0.5)) throw ConfigError("diagnose uav: alpha must be in (0, 0.5)");
  if (!(o.split_fraction > 0.2 && o.split_fraction < 0.9)) throw ConfigError("diagnose uav: split fraction must be in (0.2, 0.9)");
  if (data.observer.size() < 2) throw ConfigError("diagnose uav: observer.csv needs at least 2 rows");
  const bool with_truth = data.truth.size() >= 2 && !o.ignore_truth;
  DiagnoseReport rep;
  rep.kind = "uav";
  const LocalLevelFrame F(data.observer.front().g, 0.0);  // x north, z east
  const PlaneSeries observer(data.observer, F);
  const PlaneSeries truth(data.truth, F);
  const double gate = o.gate_deg * kDegToRad;

  // ---- the reference track and the residuals ----
  std::vector<Ob> obs;
  int beyond_gate = 0;  // frames with detections, none within the gate
  std::vector<std::pair<double, double>> far;  // their (time, nearest residual [rad])
  std::vector<TrackObs> tobs;
  TrackFit full;
  if (with_truth) {
    rep.reference = "truth (truth.csv)";
    int missed = 0;
    for (const auto& fr : data.frames) {
      Eigen::Vector2d po, pt, po_a, po_b, pt_a, pt_b;
      const double h = 0.5;
      if (!observer.at(fr.t_s, po) || !truth.at(fr.t_s, pt) || !observer.at(fr.t_s - h, po_a) ||
          !observer.at(fr.t_s + h, po_b) || !truth.at(fr.t_s - h, pt_a) || !truth.at(fr.t_s + h, pt_b))
        continue;
      auto brg = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return std::atan2(b.y() - a.y(), b.x() - a.x()); };
      const double bt = brg(po, pt);
      double best = std::numeric_limits<double>::infinity();
      for (double b : fr.bearings_rad)
        if (std::abs(wrap_pi(b - bt)) < std::abs(best)) best = wrap_pi(b - bt);
      if (!(std::abs(best) <= gate)) {
        ++missed;
        if (!fr.bearings_rad.empty()) {
          ++beyond_gate;
          far.emplace_back(fr.t_s, best);
        }
        continue;
      }
      Ob x;
      x.t = fr.t_s;
      x.meas = bt + best;
      x.r = best;
      x.rate = wrap_pi(brg(po_b, pt_b) - brg(po_a, pt_a)) / (2 * h);
      x.range = (pt - po).norm();
      obs.push_back(x);
    }
    rep.plots_dropped = missed;
  } else {
    TrackFitOptions fo;
    fo.gate_deg = o.gate_deg;
    fo.seed = o.seed;
    tobs = track_observations(data, F);
    full = fit_cv_track(tobs, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), fo);
    rep.reference = "constant-velocity track fitted to the bearings (no truth used); object at t = " +
                    short_num(full.track.t_ref_s) + " s (" + short_num(full.track.t_ref_s - data.frames.front().t_s) +
                    " s after the first frame): " + short_num(full.track.p0_F.x()) + " m north, " +
                    short_num(full.track.p0_F.y()) + " m east of the first observer sample, velocity (" +
                    short_num(full.track.v_F.x()) + ", " + short_num(full.track.v_F.y()) + ") m/s";
    for (std::size_t k = 0; k < tobs.size(); ++k) {
      if (full.associated[k] < 0) {
        ++beyond_gate;
        const double bt = full.track.bearing(tobs[k]);
        double best = std::numeric_limits<double>::infinity();
        for (double b : tobs[k].bearings_rad)
          if (std::abs(wrap_pi(b - bt)) < std::abs(best)) best = wrap_pi(b - bt);
        far.emplace_back(tobs[k].t_s, best);
        continue;
      }
      Ob x;
      x.t = tobs[k].t_s;
      x.k = k;
      x.meas = tobs[k].bearings_rad[static_cast<std::size_t>(full.associated[k])];
      x.r = wrap_pi(x.meas - full.track.bearing(tobs[k]));
      x.rate = full.track.bearing_rate(tobs[k]);
      x.range = (full.track.at(x.t) - tobs[k].o_F).norm();
      x.J = full.track.jacobian(tobs[k]);
      obs.push_back(x);
    }
    rep.plots_dropped = static_cast<int>(data.frames.size() - obs.size());
    // Observability: the relative SE of the object's range at t_ref (along the line of sight
    // from the observer's mean position). Bearings alone fix range only through the observer's
    // own motion; a large value means the track's scale is not determined by this data.
    Eigen::Vector2d o_mean = Eigen::Vector2d::Zero();
    for (const auto& x : obs) o_mean += tobs[x.k].o_F;
    o_mean /= static_cast<double>(obs.size());
    const Eigen::Vector2d los = full.track.p0_F - o_mean;
    const double range = los.norm();
    const double se_range = std::sqrt((los / range).dot(full.cov.topLeftCorner<2, 2>() * (los / range)));
    if (!(se_range < 0.2 * range))
      rep.unexplained.push_back("the object's range is not observable from this observer path (range " + short_num(range) +
                                " m +- " + short_num(se_range) + " m): the fitted track, the gain and range-dependent "
                                "effects are unreliable; the observer must manoeuvre (or use truth)");
  }
  rep.plots_used = static_cast<int>(obs.size());
  if (obs.size() < 30)
    throw ConfigError(std::string("diagnose uav: fewer than 30 frames with a detection near the ") +
                      (with_truth ? "truth" : "fitted track"));

  // Nuisance columns: the track's position and velocity (estimated mode only).
  std::vector<Col> nuis;
  if (!with_truth)
    for (int j = 0; j < 4; ++j) nuis.push_back([j](const Ob& x) { return x.J(j); });
  const auto nn = static_cast<Eigen::Index>(nuis.size());
  auto with_nuis = [&](const std::vector<Col>& cols) {
    auto all = nuis;
    all.insert(all.end(), cols.begin(), cols.end());
    return all;
  };

  const double t0 = obs.front().t, span = obs.back().t - t0;
  std::vector<Effect> singles = {
      {"bearing_bias", {[](const Ob&) { return 1.0; }}, {"rad"}},
      {"bearing_time_offset", {[](const Ob& x) { return -x.rate; }}, {"s"}},
      {"bias_drift", {[t0](const Ob& x) { return x.t - t0; }}, {"rad_per_s"}},
  };
  std::vector<Effect> periodic, manoeuvre;
  {
    std::vector<double> periods;
    for (double P = 4; P <= span / 3; P *= 1.05) periods.push_back(P);
    for (double P : periods)
      periodic.push_back({"periodic",
                          {[P](const Ob& x) { return std::sin(2 * M_PI * x.t / P); },
                           [P](const Ob& x) { return std::cos(2 * M_PI * x.t / P); }},
                          {"period_s", "amplitude_rad"}, P, static_cast<double>(periods.size())});
  }
  if (!with_truth) {
    // A velocity change dv at tau: p(t) += dv (t - tau)+, so d bearing / d dv = J_p (t - tau)+.
    const int n_tau = 40;
    for (int i = 1; i < n_tau; ++i) {
      const double tau = t0 + span * i / n_tau;
      manoeuvre.push_back({"target_maneuver",
                           {[tau](const Ob& x) { return x.J(0) * ramp(x.t, tau); },
                            [tau](const Ob& x) { return x.J(1) * ramp(x.t, tau); }},
                           {"time_s", "dv_north_mps", "dv_east_mps"}, tau, static_cast<double>(n_tau - 1)});
    }
  }
  // Family: the single effects, periodic, (target_maneuver), and the three noise tests.
  const double m_family = 4 + (with_truth ? 0 : 1) + 3;

  // ---- robust sigma, outliers, AR(1) noise from first differences of the residuals ----
  std::vector<double> r0;
  for (const auto& x : obs) r0.push_back(x.r);
  const double sigma = 1.4826 * median_abs(r0);  // robust, about zero (the nominal mean)
  for (auto& x : obs) x.outlier = std::abs(x.r) > o.outlier_z * sigma;
  if (gate < 3 * sigma)
    rep.unexplained.push_back("the association gate (" + short_num(o.gate_deg) + " deg) is narrower than 3 robust sigma (" +
                              short_num(3 * sigma / kDegToRad) + " deg): detections of the object are lost; widen --gate-deg");
  std::vector<std::size_t> use;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (!obs[i].outlier) use.push_back(i);
  double rho = 0, f_ar = 1;
  bool correlated = false;
  {
    // For white noise the first differences have lag-1 correlation -1/2; AR(1) rho gives
    // (rho - 1) / 2, so rho = 1 + 2 r_d (a fitted track's residual is white to O(1/n)).
    std::vector<double> ru;
    for (auto i : use) ru.push_back(obs[i].r);
    const double rd = diff_lag1(ru), n = static_cast<double>(ru.size() - 1);
    rho = ar1_from_differences(ru);
    const double z = (rd + 0.5) / std::sqrt(0.5 / n);
    if (0.5 * std::erfc(z / std::sqrt(2.0)) < o.alpha / m_family) {
      correlated = true;
      f_ar = (1 + rho) / (1 - rho);  // variance inflation of regression estimates under AR(1)
    }
  }

  // ---- forward selection: LR = n ln(RSS0 / RSS1) / f_ar ~ chi2(k) (+1 dof for a scan) ----
  std::vector<Effect> chosen;
  auto cols_of = [&](const std::vector<Effect>& es) {
    std::vector<Col> c;
    for (const auto& e : es) c.insert(c.end(), e.cols.begin(), e.cols.end());
    return with_nuis(c);
  };
  auto is_chosen = [&](const std::string& n) {
    return std::any_of(chosen.begin(), chosen.end(), [&](const Effect& e) { return e.name == n; });
  };
  for (;;) {
    const Fit1 base = ols(obs, use, cols_of(chosen));
    if (!base.ok) break;
    double best_p = 1;
    const Effect* best = nullptr;
    auto consider = [&](const Effect& e) {
      auto es = chosen;
      es.push_back(e);
      const Fit1 f = ols(obs, use, cols_of(es));
      if (!f.ok) return;
      const double lr = f.n * std::log(base.rss / f.rss) / f_ar;
      const double k = static_cast<double>(e.cols.size()) + (e.scan_size > 1 ? 1 : 0);
      const double p = std::min(1.0, chi2_sf(lr, k) * e.scan_size);
      if (p < best_p) {
        best_p = p;
        best = &e;
      }
    };
    for (const auto& e : singles)
      if (!is_chosen(e.name)) consider(e);
    if (!is_chosen("periodic"))
      for (const auto& e : periodic) consider(e);
    if (!is_chosen("target_maneuver"))
      for (const auto& e : manoeuvre) consider(e);
    if (!best || best_p >= o.alpha / m_family) break;
    chosen.push_back(*best);
  }
  // Manoeuvre time: refine the coarse scan on a grid 8x finer within two steps of the best (the
  // other chosen effects held in the model); its SE is half the width of the profile
  // likelihood's 1-sigma interval {tau : 2 log L(tau) >= max - 1} (at least 1/16 step).
  // The profile is the full nonlinear fit (track, manoeuvres, effects by Gauss-Newton): the
  // linearisation about the CV track is biased in time when the manoeuvre bends the track.
  std::vector<double> tau_se(chosen.size(), 0.0);
  std::vector<Ob> use_obs;
  for (auto i : use) use_obs.push_back(obs[i]);
  auto nonlinear_rss = [&](const std::vector<Effect>& es, double& rss) {
    std::vector<double> ts;
    std::vector<Col> fx;
    for (const auto& e : es)
      if (e.name == "target_maneuver") ts.push_back(e.scan_value);
      else fx.insert(fx.end(), e.cols.begin(), e.cols.end());
    ExtTrack tr;
    Eigen::VectorXd beta;
    std::vector<double> res;
    if (!fit_extended(use_obs, tobs, full.track, ts, fx, tr, beta, res)) return false;
    rss = 0;
    for (double r : res) rss += r * r;
    return true;
  };
  for (std::size_t s = 0; s < chosen.size(); ++s) {
    if (chosen[s].name != "target_maneuver") continue;
    auto others = chosen;
    others.erase(others.begin() + static_cast<std::ptrdiff_t>(s));
    double rss0 = 0;
    if (!nonlinear_rss(others, rss0)) continue;
    const double step = span / 40;
    std::vector<Effect> cand;
    std::vector<double> lr;
    for (int q = -16; q <= 16; ++q) {
      const double tau = chosen[s].scan_value + q * step / 8;
      if (tau <= t0 || tau >= t0 + span) continue;
      Effect m = chosen[s];
      m.scan_value = tau;
      m.cols = {[tau](const Ob& x) { return x.J(0) * ramp(x.t, tau); }, [tau](const Ob& x) { return x.J(1) * ramp(x.t, tau); }};
      auto es = others;
      es.push_back(m);
      double rss = 0;
      cand.push_back(m);
      lr.push_back(nonlinear_rss(es, rss) ? static_cast<double>(use.size()) * std::log(rss0 / rss) / f_ar : 0.0);
    }
    const auto ib = static_cast<std::size_t>(std::max_element(lr.begin(), lr.end()) - lr.begin());
    double lo = cand[ib].scan_value, hi = lo;
    for (std::size_t m = 0; m < cand.size(); ++m)
      if (lr[m] >= lr[ib] - 1) lo = std::min(lo, cand[m].scan_value), hi = std::max(hi, cand[m].scan_value);
    chosen[s] = cand[ib];
    tau_se[s] = std::max(step / 16, 0.5 * (hi - lo + step / 8));
  }
  const Fit1 fin = ols(obs, use, cols_of(chosen));
  if (!fin.ok) throw ConfigError("diagnose uav: the extended model's fit is singular");

  // ---- report the chosen effects: estimate, SE (inflated for AR(1)), evidence, confounding ----
  {
    Eigen::Index col = nn;
    for (std::size_t s = 0; s < chosen.size(); ++s) {
      const Effect& c = chosen[s];
      EffectResult e;
      e.name = c.name;
      e.params = c.params;
      auto se = [&](Eigen::Index j) { return std::sqrt(f_ar * fin.cov(j, j)); };
      if (c.name == "periodic") {
        e.estimate = {c.scan_value, std::hypot(fin.beta(col), fin.beta(col + 1))};
        e.stderr_ = {0, std::sqrt(f_ar * 0.5 * (fin.cov(col, col) + fin.cov(col + 1, col + 1)))};
      } else if (c.name == "target_maneuver") {
        const double step = span / 40;
        e.estimate = {c.scan_value, fin.beta(col), fin.beta(col + 1)};
        e.stderr_ = {tau_se[s], se(col), se(col + 1)};
        e.note = "velocity change at the scanned time (grid step " + short_num(step) +
                 " s, refined to " + short_num(step / 8) + " s; time SE from the profile likelihood)";
      } else {
        e.estimate = {fin.beta(col)};
        e.stderr_ = {se(col)};
      }
      auto others = chosen;
      others.erase(others.begin() + static_cast<std::ptrdiff_t>(s));
      const Fit1 f0 = ols(obs, use, cols_of(others));
      e.evidence_lr = fin.n * std::log(f0.rss / fin.rss) / f_ar;
      const double k = static_cast<double>(c.cols.size());
      e.p_value = std::min(1.0, chi2_sf(e.evidence_lr, k + (c.scan_size > 1 ? 1 : 0)) * c.scan_size);
      e.delta_bic = e.evidence_lr - k * std::log(fin.n);
      // Confounding: how well the other candidates (each with the nuisance) reproduce this
      // effect's columns: canonical correlation via the fraction of its norm they explain.
      auto explained = [&](const std::vector<Col>& by) {
        if (by.empty()) return 0.0;
        double worst = 1;
        for (const auto& cc : c.cols) {
          std::vector<Ob> tmp;
          tmp.reserve(use.size());
          std::vector<std::size_t> idx;
          for (auto i : use) {
            Ob x = obs[i];
            x.r = cc(obs[i]);
            idx.push_back(tmp.size());
            tmp.push_back(x);
          }
          double tss = 0;
          for (const auto& x : tmp) tss += x.r * x.r;
          const Fit1 g = ols(tmp, idx, by);
          if (!g.ok || tss <= 0) continue;
          worst = std::min(worst, std::sqrt(std::max(0.0, 1 - g.rss / tss)));
        }
        return worst;
      };
      if (c.name != "periodic" && c.name != "target_maneuver") {
        // given the rest of the model: the nuisance and the other chosen effects
        std::vector<Col> rest;
        for (const auto& oc : others) rest.insert(rest.end(), oc.cols.begin(), oc.cols.end());
        for (const auto& other : singles) {
          if (other.name == c.name) continue;
          auto by = with_nuis(rest);
          by.insert(by.end(), other.cols.begin(), other.cols.end());
          if (explained(by) > o.confound_corr) e.confounded_with.push_back(other.name);
        }
        if (!with_truth && explained(nuis) > o.confound_corr) e.confounded_with.push_back("object_track");
      }
      if (std::find(e.confounded_with.begin(), e.confounded_with.end(), "object_track") != e.confounded_with.end())
        e.note = "the fitted object's position/velocity absorbs most of it in this geometry; truth or an "
                 "observer path around the object separates them";
      rep.effects.push_back(e);
      col += static_cast<Eigen::Index>(c.cols.size());
    }
  }

  // ---- detection limits: each single effect alone (with the nuisance), z * SE ----
  {
    const double z = z_two_sided(o.alpha / m_family);
    for (const auto& e : singles) {
      const Fit1 f = ols(obs, use, with_nuis(e.cols));
      if (f.ok) rep.detection_limits[e.name][e.params[0]] = z * std::sqrt(f_ar * f.cov(nn, nn));
    }
    if (!manoeuvre.empty()) {
      const Effect& mid = manoeuvre[manoeuvre.size() / 2];
      const Fit1 f = ols(obs, use, with_nuis(mid.cols));
      if (f.ok) {
        rep.detection_limits["target_maneuver"]["dv_north_mps (at mid-run)"] = z * std::sqrt(f_ar * f.cov(nn, nn));
        rep.detection_limits["target_maneuver"]["dv_east_mps (at mid-run)"] = z * std::sqrt(f_ar * f.cov(nn + 1, nn + 1));
      }
    }
  }

  // ---- noise_scale, outliers, correlated_noise ----
  {
    // An outlier lies beyond thr = min(gate, outlier_z sigma): an associated frame beyond it, or a
    // frame whose detections all miss the gate; under the nominal model a frame does so with
    // probability erfc(thr / (sigma sqrt 2)).
    const double thr = std::min(gate, o.outlier_z * sigma);
    int n_out = beyond_gate;
    for (const auto& x : obs) n_out += std::abs(x.r) > thr;
    const int n_frames = static_cast<int>(obs.size()) + beyond_gate;
    const double lambda = static_cast<double>(n_frames) * std::erfc(thr / (sigma * std::sqrt(2.0)));
    const double tail = poisson_upper_tail(n_out, lambda);
    const bool outliers_found = n_out > 0 && tail < o.alpha / m_family;
    const double kpar = static_cast<double>(fin.beta.size());
    const double dof = (fin.n - kpar) / f_ar;
    const double s2 = fin.rss / (fin.n - kpar);
    const double nom = o.sigma_deg * kDegToRad, q = s2 / (nom * nom);
    const double p = 2 * std::min(chi2_sf(dof * q, dof), 1 - chi2_sf(dof * q, dof));
    if (p < o.alpha / m_family) {
      EffectResult e;
      e.name = "noise_scale";
      e.params = {"ratio"};
      e.estimate = {std::sqrt(q)};
      e.stderr_ = {std::sqrt(q) / std::sqrt(2 * dof)};
      if (outliers_found) {
        // Outliers below the 5 sigma cut still inflate the RMS: estimate sigma robustly (MAD of
        // the extended model's residuals); the MAD's efficiency 0.37 widens the SE by 1.64.
        std::vector<double> res;
        const auto cols = cols_of(chosen);
        for (auto i : use) {
          double pred = 0;
          for (std::size_t j = 0; j < cols.size(); ++j) pred += fin.beta(static_cast<Eigen::Index>(j)) * cols[j](obs[i]);
          res.push_back(obs[i].r - pred);
        }
        const double ratio = 1.4826 * median_abs(res) / nom;
        e.estimate = {ratio};
        e.stderr_ = {1.64 * ratio / std::sqrt(2 * dof)};
      }
      e.p_value = p;
      e.evidence_lr = dof * (q - 1 - std::log(q));
      e.note = "fitted bearing sigma " + short_num(std::sqrt(s2) / kDegToRad) + " deg against the nominal " +
               short_num(o.sigma_deg) + " deg";
      rep.effects.push_back(e);
    }
    if (outliers_found) {
      EffectResult e;
      e.name = "outliers";
      e.params = {"fraction"};
      const double fr = static_cast<double>(n_out) / static_cast<double>(n_frames);
      e.estimate = {fr};
      e.stderr_ = {std::sqrt(fr * (1 - fr) / static_cast<double>(n_frames))};
      e.p_value = tail;
      e.note = std::to_string(n_out) + " of " + std::to_string(n_frames) + " frames with the detection nearest the reference beyond " +
               short_num(thr / sigma) + " robust sigma (" + std::to_string(beyond_gate) + " beyond the gate)";
      rep.effects.push_back(e);
    }
    if (correlated) {
      const double dt = span / std::max<double>(1, static_cast<double>(obs.size()) - 1);
      const double r = std::clamp(rho, 1e-6, 0.99);
      EffectResult e;
      e.name = "correlated_noise";
      e.params = {"tau_s"};
      e.estimate = {-dt / std::log(r)};
      // delta method: d tau / d rho = dt / (rho ln^2 rho); SE(rho) = 2 SE(r_d) = 2 sqrt(1/(2n))
      e.stderr_ = {dt / (r * std::log(r) * std::log(r)) * 2 * std::sqrt(0.5 / static_cast<double>(obs.size()))};
      e.p_value = 0;
      e.note = "AR(1) lag-1 coefficient " + short_num(rho) + " from first differences";
      rep.effects.push_back(e);
    }
  }

  // ---- out-of-sample gain: fit on the first split_fraction of the span, score the rest ----
  const double split = t0 + o.split_fraction * span;
  rep.split_time_s = split;
  // The fits use the estimation window's non-outliers; every frame after the split is scored.
  std::vector<std::size_t> est, scr;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (obs[i].t >= split) scr.push_back(i);
    else if (!obs[i].outlier) est.push_back(i);
  // Non-track effect columns of the chosen model (manoeuvres act on the track instead).
  std::vector<Col> fx_cols;
  std::vector<double> taus;
  for (const auto& c : chosen)
    if (c.name == "target_maneuver") taus.push_back(c.scan_value);
    else fx_cols.insert(fx_cols.end(), c.cols.begin(), c.cols.end());
  Scored sc;
  if (with_truth) {
    const Fit1 fe = ols(obs, est, fx_cols);
    if (fe.ok && est.size() >= 10 && !scr.empty()) {
      auto pred = [&](std::size_t i) {
        double p = 0;
        for (std::size_t j = 0; j < fx_cols.size(); ++j) p += fe.beta(static_cast<Eigen::Index>(j)) * fx_cols[j](obs[i]);
        return p;
      };
      for (auto i : est) sc.est_r1.push_back(obs[i].r - pred(i));
      for (auto i : scr) {
        sc.t.push_back(obs[i].t);
        sc.r0.push_back(obs[i].r);
        sc.r1.push_back(obs[i].r - pred(i));
      }
    }
  } else if (est.size() >= 30 && !scr.empty()) [&] {
    // Nominal: the CV track fitted to the estimation window. Extended: the CV track with the
    // chosen manoeuvres and effect columns, Gauss-Newton on the same frames.
    std::vector<Ob> e_obs;
    for (auto i : est) e_obs.push_back(obs[i]);
    auto fit_ext = [&](bool extended, ExtTrack& tr, Eigen::VectorXd& beta, std::vector<double>& res) {
      return fit_extended(e_obs, tobs, full.track, extended ? taus : std::vector<double>{},
                          extended ? fx_cols : std::vector<Col>{}, tr, beta, res);
    };
    ExtTrack tr0, tr1;
    Eigen::VectorXd b0, b1;
    std::vector<double> res0;
    if (!fit_ext(false, tr0, b0, res0) || !fit_ext(true, tr1, b1, sc.est_r1)) {
      rep.unexplained.push_back("the track fit on the estimation window diverged: no out-of-sample gain");
      return;
    }
    ChannelGain gt;
    double ta = 0, tb = 0;
    for (auto i : scr) {
      const TrackObs& to = tobs[obs[i].k];
      auto bearing = [&](const ExtTrack& tr, const Eigen::VectorXd& beta) {
        const Eigen::Vector2d d = tr.at(to.t_s) - to.o_F;
        double h = std::atan2(d.y(), d.x());
        for (Eigen::Index j = 0; j < beta.size(); ++j) h += beta(j) * fx_cols[static_cast<std::size_t>(j)](obs[i]);
        return h;
      };
      sc.t.push_back(obs[i].t);
      sc.r0.push_back(wrap_pi(obs[i].meas - bearing(tr0, b0)));
      sc.r1.push_back(wrap_pi(obs[i].meas - bearing(tr1, b1)));
      Eigen::Vector2d pt;
      if (data.truth.size() >= 2 && truth.at(to.t_s, pt)) {
        ta += (tr0.at(to.t_s) - pt).squaredNorm();
        tb += (tr1.at(to.t_s) - pt).squaredNorm();
        ++gt.n;
      }
    }
    if (gt.n > 0) {
      gt.nominal_rms = std::sqrt(ta / gt.n);
      gt.extended_rms = std::sqrt(tb / gt.n);
      rep.gain["truth_position_m"] = gt;
    }
  }();
  // Frames beyond the gate are scored too (their nearest detection, the same under both models:
  // a model difference is small against the gate), so the nominal model pays for them.
  if (!sc.r0.empty())
    for (const auto& [t, r] : far)
      if (t >= split) {
        const auto at = std::lower_bound(sc.t.begin(), sc.t.end(), t) - sc.t.begin();
        sc.t.insert(sc.t.begin() + at, t);
        sc.r0.insert(sc.r0.begin() + at, r);
        sc.r1.insert(sc.r1.begin() + at, r);
      }
  if (!sc.r0.empty() && sc.est_r1.size() >= 10) {
    // Bearing channel: residual RMS, and the out-of-sample log-likelihood of the nominal model
    // (zero mean, white, the nominal sigma_deg) against the extended one (its mean effects, and
    // its noise effects fitted in the estimation window: sigma if noise_scale was found, AR(1)
    // with the correlation time of the estimation window's residuals if correlated_noise was).
    auto found = [&](const char* n) {
      return std::any_of(rep.effects.begin(), rep.effects.end(), [&](const EffectResult& e) { return e.name == n; });
    };
    const bool has_scale = found("noise_scale");
    // outliers: a two-component mixture with the estimation window's outlier share and RMS
    double p_out = 0, s_out = 0;
    if (found("outliers")) {
      int n_e = 0, n_o = 0;
      double so = 0;
      for (const auto& x : obs)
        if (x.t < split) {
          ++n_e;
          if (x.outlier) ++n_o, so += x.r * x.r;
        }
      for (const auto& [t, r] : far)
        if (t < split) ++n_e, ++n_o, so += r * r;
      if (n_o > 0) p_out = static_cast<double>(n_o) / n_e, s_out = std::sqrt(so / n_o);
    }
    const double s_nom = o.sigma_deg * kDegToRad;
    double ss = 0;
    for (double r : sc.est_r1) ss += r * r;
    const double s_ext = has_scale ? std::sqrt(ss / static_cast<double>(sc.est_r1.size())) : s_nom;
    const double dt = span / std::max<double>(1, static_cast<double>(obs.size()) - 1);
    const double tau_ext = correlated ? -dt / std::log(std::clamp(ar1_from_differences(sc.est_r1), 1e-6, 0.99)) : 0.0;
    // RMS over the associated frames (those within the gate); the likelihood over all scored.
    ChannelGain g;
    double a2 = 0, b2 = 0;
    for (std::size_t i = 0; i < sc.r0.size(); ++i)
      if (std::abs(sc.r0[i]) <= gate) {
        a2 += sc.r0[i] * sc.r0[i];
        b2 += sc.r1[i] * sc.r1[i];
        ++g.n;
      }
    g.nominal_rms = std::sqrt(a2 / std::max(1, g.n));
    g.extended_rms = std::sqrt(b2 / std::max(1, g.n));
    g.nominal_loglik = ar1_loglik(sc.t, sc.r0, gate, s_nom, 0.0);
    g.extended_loglik = ar1_loglik(sc.t, sc.r1, gate, s_ext, tau_ext, p_out, s_out);
    rep.gain["bearing_rad"] = g;
  }

  // ---- rows for plots (channel 0 = bearing residual; 1 = bearing rate; 2 = range) ----
  auto fitted = [&](const Ob& x) {
    double pred = 0;
    const auto cols = cols_of(chosen);
    for (std::size_t j = nuis.size(); j < cols.size(); ++j) pred += fin.beta(static_cast<Eigen::Index>(j)) * cols[j](x);
    return pred;
  };
  // The nominal model's fit of the residual is zero (zero-mean noise about the reference).
  for (const auto& x : obs) rep.rows.push_back({x.t, {x.r, x.rate, x.range}, {0, 0, 0}, {fitted(x), 0, 0}, x.outlier});

  // ---- unexplained: residual correlation with range, bearing rate and time after the extended model ----
  {
    const auto cols = cols_of(chosen);
    const char* names[3] = {"range", "bearing rate", "time"};
    for (int v = 0; v < 3; ++v) {
      std::vector<double> xs, rs;
      for (auto i : use) {
        double pred = 0;
        for (std::size_t j = 0; j < cols.size(); ++j) pred += fin.beta(static_cast<Eigen::Index>(j)) * cols[j](obs[i]);
        xs.push_back(v == 0 ? obs[i].range : v == 1 ? obs[i].rate : obs[i].t);
        rs.push_back(obs[i].r - pred);
      }
      const double c = pearson(xs, rs);
      if (c == 0) continue;
      const double z = std::abs(c) * std::sqrt(static_cast<double>(xs.size()) / f_ar);
      if (std::erfc(z / std::sqrt(2.0)) * 3 < o.alpha)
        rep.unexplained.push_back(std::string("bearing residual correlates with ") + names[v] + " (r = " +
                                  short_num(c) + ") after the extended model");
    }
    if (!with_truth) {
      const double frac = 1.0 - static_cast<double>(obs.size()) / static_cast<double>(std::max<std::size_t>(1, tobs.size()));
      if (frac > 0.2)
        rep.unexplained.push_back(short_num(100 * frac) + " % of the frames with detections have none within " +
                                  short_num(o.gate_deg) + " deg of the fitted constant-velocity track");
    }
  }
  return rep;
}

}  // namespace rnav
