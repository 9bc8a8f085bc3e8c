#include "prl_diagnose.hpp"

#include "config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

namespace rnav {

namespace {

const char* kCh[3] = {"range", "course", "glide"};

struct Obs {
  double t = 0;
  std::array<double, 3> y{};     // meas - nav  [m, rad, rad]
  std::array<double, 3> meas{};  // measured polar
  double D = 0, Ek = 0, Eg = 0;  // nav polar
  Eigen::Matrix3d J;             // d(D, Ek, Eg)/dp at the nav position
  Eigen::Vector3d rate;          // d(D, Ek, Eg)/dt from the nav velocity
  bool outlier = false;
};

using ColFn = std::function<Eigen::MatrixXd(const Obs&)>;  // 3 x k block for one plot

struct Candidate {
  std::string name;
  std::vector<std::string> params;
  std::vector<ColFn> variants;      // more than one: a scanned effect (max over the scan)
  std::vector<double> variant_par;  // the scanned value (time, period)
};

struct Fit {
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov;
  std::array<double, 3> rss{}, n{};
  double loglik = 0;
  int p = 0;
  bool ok = false;
};

// Per-channel noise covariance of the residuals over obs[idx]:
//   C_c(i, j) = s_c^2 rho_c^(|t_i - t_j| / dt) + g_c(i) g_c(j) sigma_n^2 exp(-|t_i - t_j| / tau_n)
// (radar noise, white or AR(1) with coefficient rho_c per plot interval, plus the nav solution's
// Gauss-Markov error projected onto the channel: g = 1, 1/h, 1/D). Whitening by its Cholesky
// factor turns the fit into ordinary least squares (generalised least squares).
struct Whitener {
  std::array<Eigen::LLT<Eigen::MatrixXd>, 3> llt;
};

struct NoiseModel {
  std::array<double, 3> sigma{1, 1, 1};
  std::array<double, 3> rho{0, 0, 0};  // radar noise AR(1) coefficient per plot interval dt
  double dt = 1;
  double nav_sigma = 0, nav_tau = 1;
  mutable std::map<std::pair<std::vector<std::size_t>, std::array<double, 6>>, Whitener> cache;

  const Whitener& whitener(const std::vector<Obs>& obs, const std::vector<std::size_t>& idx) const {
    const auto key = std::make_pair(idx, std::array<double, 6>{sigma[0], sigma[1], sigma[2],
                                                                 rho[0], rho[1], rho[2]});
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    Whitener w;
    const auto n = static_cast<Eigen::Index>(idx.size());
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, n);
      for (Eigen::Index i = 0; i < n; ++i) {
        const Obs& a = obs[idx[i]];
        const double ga = c == 0 ? 1.0 : c == 1 ? 1.0 / (a.D * std::cos(a.Eg)) : 1.0 / a.D;
        for (Eigen::Index j = 0; j <= i; ++j) {
          const Obs& b = obs[idx[j]];
          // radar noise: sigma^2 rho^(|t_i - t_j| / dt) (white when rho = 0)
          const double lag = std::abs(a.t - b.t) / dt;
          const double radar = i == j ? sigma[c] * sigma[c]
                               : rho[c] > 0 ? sigma[c] * sigma[c] * std::pow(rho[c], lag) : 0.0;
          C(i, j) += radar;
          if (j != i) C(j, i) += radar;
          if (nav_sigma <= 0) continue;
          const double gb = c == 0 ? 1.0 : c == 1 ? 1.0 / (b.D * std::cos(b.Eg)) : 1.0 / b.D;
          const double v = ga * gb * nav_sigma * nav_sigma * std::exp(-std::abs(a.t - b.t) / nav_tau);
          C(i, j) += v;
          if (j != i) C(j, i) += v;
        }
      }
      w.llt[c].compute(C);
    }
    return cache.emplace(key, std::move(w)).first->second;
  }
};

// Generalised least squares of y on [per-channel bias | effect columns] over obs[idx].
Fit fit(const std::vector<Obs>& obs, const std::vector<std::size_t>& idx,
        const std::vector<ColFn>& fns, const NoiseModel& nm) {
  int k = 3;
  std::vector<int> widths;
  for (const auto& f : fns) {
    widths.push_back(static_cast<int>(f(obs[idx.front()]).cols()));
    k += widths.back();
  }
  const auto n = static_cast<Eigen::Index>(idx.size());
  const Whitener& W = nm.whitener(obs, idx);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(k, k);
  Eigen::VectorXd bvec = Eigen::VectorXd::Zero(k);
  std::array<Eigen::MatrixXd, 3> Xw;
  std::array<Eigen::VectorXd, 3> yw;
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, k);
    Eigen::VectorXd y(n);
    for (Eigen::Index r = 0; r < n; ++r) {
      const Obs& o = obs[idx[r]];
      int col = 3;
      for (std::size_t j = 0; j < fns.size(); ++j) {
        X.block(r, col, 1, widths[j]) = fns[j](o).row(c);
        col += widths[j];
      }
      X(r, c) = 1;
      y(r) = o.y[c];
    }
    Xw[c] = W.llt[c].matrixL().solve(X);
    yw[c] = W.llt[c].matrixL().solve(y);
    A += Xw[c].transpose() * Xw[c];
    bvec += Xw[c].transpose() * yw[c];
  }
  Fit f;
  // Equilibrate (columns differ by many orders of magnitude: metres, radians, range x gain).
  Eigen::VectorXd dsc(k);
  for (int i = 0; i < k; ++i) dsc(i) = A(i, i) > 0 ? 1.0 / std::sqrt(A(i, i)) : 1.0;
  const Eigen::MatrixXd As = dsc.asDiagonal() * A * dsc.asDiagonal();
  Eigen::LDLT<Eigen::MatrixXd> ldlt(As);
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-12) return f;
  f.beta = dsc.asDiagonal() * ldlt.solve(dsc.asDiagonal() * bvec);
  f.cov = dsc.asDiagonal() * ldlt.solve(Eigen::MatrixXd::Identity(k, k)) * dsc.asDiagonal();
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd r = yw[c] - Xw[c] * f.beta;
    f.rss[c] = r.squaredNorm();
    f.n[c] = static_cast<double>(n);
    // Profile log-likelihood with an unknown scale per channel (whitened residuals).
    f.loglik += -0.5 * f.n[c] * std::log(f.rss[c] / f.n[c]);
  }
  // The whitened residuals have unit variance under the model: scale cov by the fitted scale.
  double scale = 0, nn = 0;
  for (int c = 0; c < 3; ++c) {
    scale += f.rss[c];
    nn += f.n[c];
  }
  f.cov *= std::max(1.0, scale / std::max(1.0, nn - k));
  f.p = k;
  f.ok = true;
  return f;
}

// Largest canonical correlation between two column sets (after removing per-channel means,
// weighted): 1 means the data cannot tell them apart.
double canonical_corr(const std::vector<Obs>& obs, const std::vector<std::size_t>& idx,
                      const ColFn& a, const ColFn& b, const std::array<double, 3>& sigma) {  // white approximation
  const Eigen::Index rows = static_cast<Eigen::Index>(3 * idx.size());
  const int ka = static_cast<int>(a(obs[idx[0]]).cols()), kb = static_cast<int>(b(obs[idx[0]]).cols());
  Eigen::MatrixXd A(rows, ka), B(rows, kb);
  for (std::size_t r = 0; r < idx.size(); ++r) {
    A.block(3 * r, 0, 3, ka) = a(obs[idx[r]]);
    B.block(3 * r, 0, 3, kb) = b(obs[idx[r]]);
    for (int c = 0; c < 3; ++c) {
      A.row(3 * r + c) /= sigma[c];
      B.row(3 * r + c) /= sigma[c];
    }
  }
  for (int c = 0; c < 3; ++c) {  // remove each channel's mean (the bias columns)
    for (auto* M : {&A, &B}) {
      Eigen::RowVectorXd m = Eigen::RowVectorXd::Zero(M->cols());
      for (std::size_t r = 0; r < idx.size(); ++r) m += M->row(3 * r + c);
      m /= static_cast<double>(idx.size());
      for (std::size_t r = 0; r < idx.size(); ++r) M->row(3 * r + c) -= m;
    }
  }
  auto basis = [](const Eigen::MatrixXd& M) -> Eigen::MatrixXd {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeThinU);
    int rank = 0;
    for (Eigen::Index i = 0; i < svd.singularValues().size(); ++i)
      if (svd.singularValues()(i) > 1e-9 * svd.singularValues()(0)) ++rank;
    return svd.matrixU().leftCols(rank);
  };
  const Eigen::MatrixXd Qa = basis(A), Qb = basis(B);
  if (Qa.cols() == 0 || Qb.cols() == 0) return 0;
  Eigen::JacobiSVD<Eigen::MatrixXd> s(Qa.transpose() * Qb);
  return s.singularValues()(0);
}

double lag1(const std::vector<double>& r) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    den += r[i] * r[i];
    if (i) num += r[i] * r[i - 1];
  }
  return den > 0 ? num / den : 0;
}

}  // namespace

DiagnoseReport diagnose_prl(const PrlFlightData& data, const DiagnoseOptions& o) {
  DiagnoseReport rep;
  rep.split_time_s = o.split_time_s;
  const LocalLevelFrame R = data.radar_frame();
  // Nav in R, then residuals at plot times (linear interpolation; velocity from the bracket).
  std::vector<Eigen::Vector3d> nav_R;
  for (const auto& s : data.nav) nav_R.push_back(R.from_geodetic(s.g));
  std::vector<Obs> obs;
  std::size_t j = 0;
  for (std::size_t i = 0; i < data.plots.size(); ++i) {
    const double t = data.t_s[i];
    while (j + 1 < data.nav.size() && data.nav[j + 1].t_s < t) ++j;
    if (j + 1 >= data.nav.size() || data.nav[j].t_s > t ||
        data.nav[j + 1].t_s - data.nav[j].t_s > o.max_nav_gap_s) {
      ++rep.plots_dropped;
      continue;
    }
    const double t0 = data.nav[j].t_s, t1 = data.nav[j + 1].t_s, a = (t - t0) / (t1 - t0);
    const Eigen::Vector3d p = (1 - a) * nav_R[j] + a * nav_R[j + 1];
    const Eigen::Vector3d v = (nav_R[j + 1] - nav_R[j]) / (t1 - t0);
    const Polar q = polar_from_cartesian(p);
    Obs ob;
    ob.t = t;
    ob.D = q.range_m;
    ob.Ek = q.course_rad;
    ob.Eg = q.glide_rad;
    ob.J = polar_jacobian(p);
    ob.rate = ob.J * v;
    const Polar& m = data.plots[i];
    ob.meas = {m.range_m, m.course_rad, m.glide_rad};
    ob.y = {m.range_m - q.range_m, wrap_pi(m.course_rad - q.course_rad), m.glide_rad - q.glide_rad};
    obs.push_back(ob);
  }
  rep.plots_used = static_cast<int>(obs.size());
  if (obs.size() < 30) throw ConfigError("diagnose: fewer than 30 plots with a nav solution around them");

  // ---- the catalogue as regressors ----
  const Eigen::Matrix3d R_R_ENU = [&] {
    const double b = data.azimuth_reference_deg * kDegToRad;
    Eigen::Matrix3d M;
    M << std::sin(b), std::cos(b), 0, 0, 0, 1, std::cos(b), -std::sin(b), 0;
    return M;
  }();
  auto col3 = [](double a, double b, double c) {
    Eigen::MatrixXd m(3, 1);
    m << a, b, c;
    return m;
  };
  std::vector<Candidate> cands;
  cands.push_back({"range_gain", {"g"}, {[&](const Obs& x) { return col3(x.D, 0, 0); }}, {}});
  cands.push_back({"time_offset", {"tau_s"}, {[&](const Obs& x) { return col3(-x.rate[0], -x.rate[1], -x.rate[2]); }}, {}});
  cands.push_back({"elevation_refraction", {"k_rad"}, {[&](const Obs& x) { return col3(0, 0, 1.0 / std::tan(x.Eg)); }}, {}});
  cands.push_back({"azimuth_elevation_coupling", {"c_rad"}, {[&](const Obs& x) { return col3(0, std::tan(x.Eg), 0); }}, {}});
  cands.push_back({"site_offset", {"east_m", "north_m", "up_m"},
                   {[&](const Obs& x) -> Eigen::MatrixXd { return x.J * R_R_ENU; }}, {}});
  const char* drift_units[3] = {"range_mps", "course_radps", "glide_radps"};
  for (int c = 0; c < 3; ++c)
    cands.push_back({"bias_drift", {drift_units[c]}, {[c](const Obs& x) {
                       Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3, 1);
                       m(c, 0) = x.t;
                       return m;
                     }}, {}});
  const double t_lo = obs.front().t, t_hi = obs.back().t, span = t_hi - t_lo;
  const char* step_units[3] = {"range_m", "course_rad", "glide_rad"};
  for (int c = 0; c < 3; ++c) {
    Candidate step{"bias_step", {step_units[c]}, {}, {}};
    for (double ts = t_lo + 0.1 * span; ts <= t_lo + 0.9 * span; ts += span / 40) {
      step.variants.push_back([ts, c](const Obs& x) -> Eigen::MatrixXd {
        Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3, 1);
        m(c, 0) = x.t >= ts ? 1.0 : 0.0;
        return m;
      });
      step.variant_par.push_back(ts);
    }
    cands.push_back(step);
    Candidate per{"periodic", {"period_s", std::string("amplitude_") + step_units[c]}, {}, {}};
    for (double P = 4; P <= span / 3; P *= 1.05) {
      per.variants.push_back([P, c](const Obs& x) -> Eigen::MatrixXd {
        Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3, 2);
        m(c, 0) = std::sin(2 * M_PI * x.t / P);
        m(c, 1) = std::cos(2 * M_PI * x.t / P);
        return m;
      });
      per.variant_par.push_back(P);
    }
    cands.push_back(per);
  }
  const double m_family = static_cast<double>(cands.size()) + 3;  // + the three noise tests

  std::vector<std::size_t> all;
  for (std::size_t i = 0; i < obs.size(); ++i) all.push_back(i);
  auto usable = [&](const std::vector<std::size_t>& idx) {
    std::vector<std::size_t> u;
    for (auto i : idx)
      if (!obs[i].outlier) u.push_back(i);
    return u;
  };

  // Noise levels: from the data (robust, per channel) - the nominal sigma options are only used
  // for the noise_scale test.
  NoiseModel nm;
  nm.nav_sigma = o.nav_sigma_m;
  nm.nav_tau = o.nav_tau_s;
  auto& sigma = nm.sigma;
  auto set_sigma_and_outliers = [&](const std::vector<double>& pred_flat) {
    for (int c = 0; c < 3; ++c) {
      std::vector<double> r;
      for (std::size_t i = 0; i < obs.size(); ++i) r.push_back(obs[i].y[c] - pred_flat[3 * i + c]);
      sigma[c] = 1.4826 * median_abs(r);
      if (!(sigma[c] > 0)) sigma[c] = 1e-12;
    }
    for (std::size_t i = 0; i < obs.size(); ++i) {
      obs[i].outlier = false;
      for (int c = 0; c < 3; ++c)
        if (std::abs(obs[i].y[c] - pred_flat[3 * i + c]) > o.outlier_z * sigma[c]) obs[i].outlier = true;
    }
  };
  // Prediction of a fitted model at every plot.
  auto predict = [&](const Fit& f, const std::vector<ColFn>& fns) {
    std::vector<double> out(3 * obs.size());
    for (std::size_t i = 0; i < obs.size(); ++i) {
      Eigen::MatrixXd X = Eigen::MatrixXd::Identity(3, 3);
      for (const auto& fn : fns) {
        Eigen::MatrixXd B = fn(obs[i]);
        Eigen::MatrixXd X2(3, X.cols() + B.cols());
        X2 << X, B;
        X = X2;
      }
      const Eigen::Vector3d yhat = X * f.beta;
      for (int c = 0; c < 3; ++c) out[3 * i + c] = yhat[c];
    }
    return out;
  };

  // Forward selection (optionally repeated with AR(1) inflation).
  struct Chosen {
    std::size_t cand;
    std::size_t variant;
  };
  std::vector<Chosen> chosen;
  auto fns_of = [&](const std::vector<Chosen>& ch) {
    std::vector<ColFn> f;
    for (const auto& c : ch) f.push_back(cands[c.cand].variants[c.variant]);
    return f;
  };
  auto select = [&]() {
    chosen.clear();
    for (;;) {
      const auto idx = usable(all);
      const Fit base = fit(obs, idx, fns_of(chosen), nm);
      double best_p = 1;
      Chosen best{0, 0};
      bool found = false;
      for (std::size_t c = 0; c < cands.size(); ++c) {
        if (std::any_of(chosen.begin(), chosen.end(), [&](const Chosen& x) { return x.cand == c; })) continue;
        for (std::size_t v = 0; v < cands[c].variants.size(); ++v) {
          auto ch = chosen;
          ch.push_back({c, v});
          const Fit f = fit(obs, idx, fns_of(ch), nm);
          if (!f.ok) continue;
          const double lr = 2 * (f.loglik - base.loglik);
          const double k = f.p - base.p + (cands[c].variants.size() > 1 ? 1 : 0);
          const double p = std::min(1.0, chi2_sf(lr, k) * cands[c].variants.size());
          if (p < best_p) {
            best_p = p;
            best = {c, v};
            found = true;
          }
        }
      }
      if (!found || best_p >= o.alpha / m_family) break;
      chosen.push_back(best);
    }
  };

  double dt_med = span / std::max<std::size_t>(1, obs.size() - 1);
  nm.dt = dt_med;
  auto residuals = [&](const Fit& f, const std::vector<ColFn>& fns, int c) {
    const auto pred = predict(f, fns);
    std::vector<double> r;
    for (std::size_t i = 0; i < obs.size(); ++i)
      if (!obs[i].outlier) r.push_back(obs[i].y[c] - pred[3 * i + c]);
    return r;
  };
  // Pass 1: nominal fit -> robust sigma, outliers.
  const Fit f0 = [&] {
    NoiseModel white;  // unit weights, no nav term: only for the first robust sigma
    return fit(obs, all, {}, white);
  }();
  set_sigma_and_outliers(predict(f0, {}));
  // Correlated radar noise, judged on first differences of the nominal residuals, which slow
  // systematic effects hardly touch: for AR(1) noise the differences' lag-1 autocorrelation is
  // -(1 - rho)/2, so rho = 1 + 2 r_d; under white noise r_d = -1/2 with variance 0.5/n
  // (Bartlett's formula for an MA(1) with theta = -1).
  std::array<double, 3> rho{}, se_rho{};
  bool correlated = false;
  for (int c = 0; c < 3; ++c) {
    const auto r = residuals(f0, {}, c);
    std::vector<double> d;
    for (std::size_t i = 1; i < r.size(); ++i) d.push_back(r[i] - r[i - 1]);
    const double rd = lag1(d), n = static_cast<double>(d.size());
    const double z = (rd + 0.5) / std::sqrt(0.5 / n);
    rho[c] = std::clamp(1 + 2 * rd, 0.0, 0.99);
    se_rho[c] = 2 * std::sqrt(0.5 / n);
    if (0.5 * std::erfc(z / std::sqrt(2.0)) * 3 < o.alpha / m_family) correlated = true;
  }
  if (correlated) nm.rho = rho;
  select();
  {
    const Fit f1 = fit(obs, usable(all), fns_of(chosen), nm);
    set_sigma_and_outliers(predict(f1, fns_of(chosen)));
    select();
  }
  Fit final_fit = fit(obs, usable(all), fns_of(chosen), nm);

  // ---- detection limits: each single-column-group effect added alone to the nominal model ----
  {
    // two-sided z at alpha / m_family (bisection on erfc)
    double lo = 0, hi = 10;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (std::erfc(mid / std::sqrt(2.0)) > o.alpha / m_family ? lo : hi) = mid;
    }
    for (const auto& cd : cands) {
      if (cd.variants.size() > 1) continue;
      const Fit f = fit(obs, usable(all), {cd.variants[0]}, nm);
      if (!f.ok) continue;
      for (std::size_t i = 0; i < cd.params.size(); ++i)
        rep.detection_limits[cd.name][cd.params[i]] = lo * std::sqrt(f.cov(3 + i, 3 + i));
    }
  }

  // ---- report: nominal biases ----
  {
    const char* names[3] = {"range_bias", "azimuth_bias", "elevation_bias"};
    const char* units[3] = {"m", "rad", "rad"};
    for (int c = 0; c < 3; ++c) {
      EffectResult e;
      e.name = names[c];
      e.nominal = true;
      e.params = {units[c]};
      e.estimate = {final_fit.beta(c)};
      e.stderr_ = {std::sqrt(final_fit.cov(c, c))};
      e.note = "nominal parameter (the paper's constant bias)";
      rep.effects.push_back(e);
    }
  }
  // ---- selected effects ----
  int col = 3;
  for (std::size_t s = 0; s < chosen.size(); ++s) {
    const Candidate& cd = cands[chosen[s].cand];
    const ColFn& fn = cd.variants[chosen[s].variant];
    const int k = static_cast<int>(fn(obs[0]).cols());
    EffectResult e;
    e.name = cd.name;
    const bool scanned = cd.variants.size() > 1;
    if (cd.name == "periodic") {
      // amplitude from the (sin, cos) pair; the period is the scanned value
      e.params = cd.params;
      e.estimate.push_back(cd.variant_par[chosen[s].variant]);
      e.stderr_.push_back(0);
      const double a = final_fit.beta(col), b = final_fit.beta(col + 1);
      e.estimate.push_back(std::hypot(a, b));
      e.stderr_.push_back(std::sqrt(0.5 * (final_fit.cov(col, col) + final_fit.cov(col + 1, col + 1))));
    } else {
      e.params = cd.params;
      for (int i = 0; i < k; ++i) {
        e.estimate.push_back(final_fit.beta(col + i));
        e.stderr_.push_back(std::sqrt(final_fit.cov(col + i, col + i)));
      }
      if (scanned) e.note = "at t = " + short_num(cd.variant_par[chosen[s].variant]) + " s";
    }
    // Evidence: the final model against the final model without this effect.
    auto without = chosen;
    without.erase(without.begin() + static_cast<long>(s));
    const Fit f0 = fit(obs, usable(all), fns_of(without), nm);
    e.evidence_lr = 2 * (final_fit.loglik - f0.loglik);
    const double kk = k + (scanned ? 1 : 0);
    e.p_value = std::min(1.0, chi2_sf(e.evidence_lr, kk) * cd.variants.size());
    double n_eff = 0;
    for (int c = 0; c < 3; ++c) n_eff += final_fit.n[c];
    e.delta_bic = e.evidence_lr - kk * std::log(n_eff);
    // Confounding with every other catalogue effect in this geometry.
    for (std::size_t c2 = 0; c2 < cands.size(); ++c2) {
      if (c2 == chosen[s].cand || cands[c2].variants.size() > 1 || scanned) continue;
      const double cc = canonical_corr(obs, usable(all), fn, cands[c2].variants[0], sigma);
      if (cc > o.confound_corr) e.confounded_with.push_back(cands[c2].name);
    }
    if (!e.confounded_with.empty())
      e.note += (e.note.empty() ? "" : "; ") + std::string("cannot be told apart here from ") +
                e.confounded_with.front() +
                " (their regressors are nearly proportional along this path); a path with "
                "different range rate, elevation and azimuth history (e.g. a level pass at "
                "constant range, or an approach from another direction) would separate them";
    rep.effects.push_back(e);
    col += k;
  }
  // ---- noise tests ----
  const double nominal_sigma[3] = {o.sigma_range_m, o.sigma_course_deg * kDegToRad, o.sigma_glide_deg * kDegToRad};
  {
    EffectResult e;
    e.name = "noise_scale";
    e.params = {"range", "course", "glide"};
    bool any = false;
    double lr_sum = 0;
    const auto pred = predict(final_fit, fns_of(chosen));
    for (int c = 0; c < 3; ++c) {
      // The radar's noise sigma from the raw residuals of the final model (nav part removed in
      // variance), against the nominal; effective dof n (1 - rho) / (1 + rho) for AR(1) noise.
      double rss = 0, n = 0;
      for (std::size_t i = 0; i < obs.size(); ++i)
        if (!obs[i].outlier) {
          const double r = obs[i].y[c] - pred[3 * i + c];
          rss += r * r;
          n += 1;
        }
      double nav_var = 0;
      for (std::size_t i = 0; i < obs.size(); ++i) {
        const double g = c == 0 ? 1.0 : c == 1 ? 1.0 / (obs[i].D * std::cos(obs[i].Eg)) : 1.0 / obs[i].D;
        nav_var += g * g * o.nav_sigma_m * o.nav_sigma_m / obs.size();
      }
      const double s2 = std::max(1e-300, rss / (n - 1) - nav_var);
      const double dof = (n - 1) * (1 - nm.rho[c]) / (1 + nm.rho[c]);
      const double ratio = std::sqrt(s2) / nominal_sigma[c];
      e.estimate.push_back(ratio);
      e.stderr_.push_back(ratio / std::sqrt(2 * dof));
      const double x = dof * s2 / (nominal_sigma[c] * nominal_sigma[c]);
      const double p = 2 * std::min(chi2_sf(x, dof), 1 - chi2_sf(x, dof)) * 3;
      const double q = s2 / (nominal_sigma[c] * nominal_sigma[c]);
      lr_sum += dof * (q - 1 - std::log(q));  // 2 log LR of sigma_hat against the nominal sigma
      if (p < o.alpha / m_family) any = true;
      e.p_value = std::min(e.p_value, std::min(1.0, p));
    }
    e.evidence_lr = lr_sum;
    e.note = "ratio of the fitted noise sigma to the nominal (options: " + short_num(o.sigma_range_m) +
             " m, " + short_num(o.sigma_course_deg) + " deg, " + short_num(o.sigma_glide_deg) + " deg)";
    if (any) rep.effects.push_back(e);
  }
  {
    int n_out = 0;
    for (const auto& ob : obs) n_out += ob.outlier;
    // Under the Gaussian model P(|z| > z0) per channel; expected count lambda
    const double p1 = std::erfc(o.outlier_z / std::sqrt(2.0));
    const double lambda = 3 * obs.size() * p1;
    const double tail = poisson_upper_tail(n_out, lambda);
    if (n_out > 0 && tail < o.alpha / m_family) {
      EffectResult e;
      e.name = "outliers";
      e.params = {"fraction"};
      const double f = static_cast<double>(n_out) / obs.size();
      e.estimate = {f};
      e.stderr_ = {std::sqrt(f * (1 - f) / obs.size())};
      e.p_value = tail;
      e.evidence_lr = -2 * std::log(std::max(tail, 1e-300));
      e.note = std::to_string(n_out) + " plots beyond " + short_num(o.outlier_z) + " robust sigma (expected " +
               short_num(lambda) + "); excluded from the fits";
      rep.effects.push_back(e);
    }
  }
  if (correlated) {
    EffectResult e;
    e.name = "correlated_noise";
    e.params = {"range_tau_s", "course_tau_s", "glide_tau_s"};
    for (int c = 0; c < 3; ++c) {
      const double r = std::clamp(rho[c], 1e-6, 0.99);
      e.estimate.push_back(-dt_med / std::log(r));
      // delta method: d tau / d rho = dt / (rho ln^2 rho)
      e.stderr_.push_back(dt_med / (r * std::log(r) * std::log(r)) * se_rho[c]);
    }
    e.note = "AR(1) radar noise, lag-1 coefficients (" + short_num(rho[0]) + ", " + short_num(rho[1]) + ", " +
             short_num(rho[2]) + ") from first differences; all fits use it";
    e.p_value = 0;
    rep.effects.push_back(e);
  }
  // ---- out-of-sample gain: fit before the split, score after it ----
  std::vector<std::size_t> est, scr;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (!obs[i].outlier) (obs[i].t < o.split_time_s ? est : scr).push_back(i);
  if (est.size() >= 30 && scr.size() >= 5) {
    const auto fns = fns_of(chosen);
    const Fit fn0 = fit(obs, est, {}, nm), fn1 = fit(obs, est, fns, nm);
    if (fn0.ok && fn1.ok) {
      const auto p0 = predict(fn0, {}), p1 = predict(fn1, fns);
      for (int c = 0; c < 3; ++c) {
        ChannelGain g;
        const double s0 = sigma[c] * std::sqrt(fn0.rss[c] / fn0.n[c]),
                     s1 = sigma[c] * std::sqrt(fn1.rss[c] / fn1.n[c]);
        double a = 0, b = 0;
        for (auto i : scr) {
          const double r0 = obs[i].y[c] - p0[3 * i + c], r1 = obs[i].y[c] - p1[3 * i + c];
          a += r0 * r0;
          b += r1 * r1;
          g.nominal_loglik += -0.5 * (r0 * r0 / (s0 * s0) + std::log(2 * M_PI * s0 * s0));
          g.extended_loglik += -0.5 * (r1 * r1 / (s1 * s1) + std::log(2 * M_PI * s1 * s1));
        }
        g.n = static_cast<int>(scr.size());
        g.nominal_rms = std::sqrt(a / scr.size());
        g.extended_rms = std::sqrt(b / scr.size());
        rep.gain[kCh[c]] = g;
      }
      // Against truth: the compensated plot's position error.
      if (!data.truth.empty()) {
        std::vector<Eigen::Vector3d> tr_R;
        for (const auto& s : data.truth) tr_R.push_back(R.from_geodetic(s.g));
        ChannelGain g;
        double a = 0, b = 0;
        std::size_t k = 0;
        for (auto i : scr) {
          const double t = obs[i].t;
          while (k + 1 < data.truth.size() && data.truth[k + 1].t_s < t) ++k;
          if (k + 1 >= data.truth.size() || data.truth[k].t_s > t) continue;
          const double w = (t - data.truth[k].t_s) / (data.truth[k + 1].t_s - data.truth[k].t_s);
          const Eigen::Vector3d pt = (1 - w) * tr_R[k] + w * tr_R[k + 1];
          auto err = [&](const std::vector<double>& pred) {
            const Polar q{obs[i].meas[0] - pred[3 * i], wrap_pi(obs[i].meas[1] - pred[3 * i + 1]),
                          obs[i].meas[2] - pred[3 * i + 2]};
            return (cartesian_from_polar(q) - pt).squaredNorm();
          };
          a += err(p0);
          b += err(p1);
          ++g.n;
        }
        if (g.n > 0) {
          g.nominal_rms = std::sqrt(a / g.n);
          g.extended_rms = std::sqrt(b / g.n);
          rep.gain["truth_position_m"] = g;
        }
      }
    }
  }

  // ---- rows for plots ----
  {
    const Fit fn = fit(obs, usable(all), {}, nm);
    const auto p0 = predict(fn, {}), p1 = predict(final_fit, fns_of(chosen));
    for (std::size_t i = 0; i < obs.size(); ++i)
      rep.rows.push_back({obs[i].t, obs[i].y, {p0[3 * i], p0[3 * i + 1], p0[3 * i + 2]},
                          {p1[3 * i], p1[3 * i + 1], p1[3 * i + 2]}, obs[i].outlier});
  }

  // ---- unexplained: residual structure left after the extended model ----
  {
    const auto fns = fns_of(chosen);
    const auto pred = predict(final_fit, fns);
    const char* vars[6] = {"time", "slant range", "elevation", "azimuth", "range rate", "cot(elevation)"};
    for (int c = 0; c < 3; ++c) {
      std::vector<double> r;
      std::vector<std::array<double, 6>> x;
      for (std::size_t i = 0; i < obs.size(); ++i)
        if (!obs[i].outlier) {
          r.push_back(obs[i].y[c] - pred[3 * i + c]);
          x.push_back({obs[i].t, obs[i].D, obs[i].Eg, obs[i].Ek, obs[i].rate[0], 1 / std::tan(obs[i].Eg)});
        }
      const double n = static_cast<double>(r.size());
      for (int v = 0; v < 6; ++v) {
        std::vector<double> xv;
        for (const auto& row : x) xv.push_back(row[v]);
        const double corr = pearson(xv, r);
        if (corr == 0) continue;
        const double z = std::abs(corr) * std::sqrt(n * (1 - rho[c]) / (1 + rho[c]));
        if (std::erfc(z / std::sqrt(2.0)) * 18 < o.alpha)
          rep.unexplained.push_back(std::string(kCh[c]) + " residual correlates with " + vars[v] +
                                    " (r = " + short_num(corr) + ") after the extended model");
      }
    }
  }
  return rep;
}

void DiagnoseReport::write_residuals_csv(const std::string& file) const {
  std::ofstream f(file);
  if (!f) throw std::runtime_error("cannot write " + file);
  char b[512];
  if (kind == "uav") {
    f << "t_s,bearing_residual_rad,bearing_extended_rad,bearing_rate_radps,range_m,outlier\n";
    for (const auto& r : rows) {
      std::snprintf(b, sizeof b, "%.3f,%.9f,%.9f,%.9f,%.3f,%d\n", r.t_s, r.y[0], r.extended[0], r.y[1], r.y[2],
                    r.outlier ? 1 : 0);
      f << b;
    }
    if (!f) throw std::runtime_error("cannot write " + file);
    return;
  }
  f << "t_s,range_m,range_nominal_m,range_extended_m,course_rad,course_nominal_rad,course_extended_rad,"
       "glide_rad,glide_nominal_rad,glide_extended_rad,outlier\n";
  for (const auto& r : rows) {
    std::snprintf(b, sizeof b, "%.3f,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%d\n", r.t_s, r.y[0],
                  r.nominal[0], r.extended[0], r.y[1], r.nominal[1], r.extended[1], r.y[2], r.nominal[2],
                  r.extended[2], r.outlier ? 1 : 0);
    f << b;
  }
}

nlohmann::ordered_json DiagnoseReport::to_json() const {
  nlohmann::ordered_json j;
  j["kind"] = kind;
  j[kind == "uav" ? "frames_used" : "plots_used"] = plots_used;
  j[kind == "uav" ? "frames_dropped" : "plots_dropped"] = plots_dropped;
  if (!reference.empty()) j["reference"] = reference;
  j["noise_levels"] = "estimated from the data (robust MAD of the residuals); the options' nominal "
                      "sigmas are used only for the noise_scale test";
  j["effects"] = nlohmann::ordered_json::array();
  for (const auto& e : effects) {
    nlohmann::ordered_json x;
    x["name"] = e.name;
    x["params"] = e.params;
    x["estimate"] = e.estimate.size() == 1 ? nlohmann::ordered_json(e.estimate[0]) : nlohmann::ordered_json(e.estimate);
    x["stderr"] = e.stderr_.size() == 1 ? nlohmann::ordered_json(e.stderr_[0]) : nlohmann::ordered_json(e.stderr_);
    x["evidence"] = {{"lr", e.evidence_lr}, {"p_value", e.p_value}, {"delta_bic", e.delta_bic}};
    x["confounded_with"] = e.confounded_with;
    x["nominal"] = e.nominal;
    if (!e.note.empty()) x["note"] = e.note;
    j["effects"].push_back(x);
  }
  j["gain"] = nlohmann::ordered_json::object();
  j["gain_window"] = "fit on t < " + short_num(split_time_s) + " s, scored on t >= " + short_num(split_time_s) + " s";
  for (const auto& [k, g] : gain)
    j["gain"][k] = {{"n", g.n}, {"nominal_rms", g.nominal_rms}, {"extended_rms", g.extended_rms},
                    {"nominal_loglik", g.nominal_loglik}, {"extended_loglik", g.extended_loglik}};
  j["unexplained"] = unexplained;
  j["detection_limits"] = detection_limits;
  return j;
}

std::string DiagnoseReport::text() const {
  std::ostringstream o;
  if (kind == "uav")
    o << "frames used " << plots_used << ", dropped (no detection within the gate, or no observer nav) "
      << plots_dropped << "\n  reference: " << reference << "\n";
  else
    o << "plots used " << plots_used << ", dropped (no nav around them) " << plots_dropped << "\n";
  for (const auto& e : effects) {
    o << (e.nominal ? "  nominal  " : "  EFFECT   ") << e.name << ":";
    for (std::size_t i = 0; i < e.estimate.size(); ++i)
      o << " " << (i < e.params.size() ? e.params[i] + "=" : "") << short_num(e.estimate[i]) << " +- "
        << short_num(e.stderr_[i]);
    if (!e.nominal) o << "  (2 log LR " << short_num(e.evidence_lr) << ", p " << short_num(e.p_value) << ")";
    if (!e.confounded_with.empty()) o << "  confounded with " << e.confounded_with.front();
    o << "\n";
  }
  for (const auto& [k, g] : gain)
    o << "  gain " << k << ": RMS " << short_num(g.nominal_rms) << " -> " << short_num(g.extended_rms) << " (n "
      << g.n << ")\n";
  for (const auto& u : unexplained) o << "  unexplained: " << u << "\n";
  return o.str();
}

}  // namespace rnav
