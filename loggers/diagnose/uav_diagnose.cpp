#include "uav_diagnose.hpp"

#include "config.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace rnav {

namespace {

struct Ob {
  double t, r, rate, range;
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
  const double s2 = f.rss / std::max(1.0, f.n - k);
  f.cov = s2 * d.asDiagonal() * ldlt.solve(Eigen::MatrixXd::Identity(k, k)) * d.asDiagonal();
  f.ok = true;
  return f;
}

}  // namespace

DiagnoseReport diagnose_uav(const AzimuthData& data, const UavDiagnoseOptions& o) {
  if (data.truth.size() < 2)
    throw ConfigError("diagnose uav: needs truth.csv (the diagnosis without truth, on an estimated "
                      "track, is not implemented yet)");
  DiagnoseReport rep;
  const LocalLevelFrame F(data.observer.front().g, 0.0);  // x north, z east
  auto interp = [&](const std::vector<GeoSample>& v, std::vector<Eigen::Vector2d>& cache, double t,
                    Eigen::Vector2d& p) {
    if (cache.empty())
      for (const auto& s : v) {
        const Eigen::Vector3d q = F.from_geodetic(s.g);
        cache.emplace_back(q.x(), q.z());
      }
    const auto it = std::lower_bound(v.begin(), v.end(), t, [](const GeoSample& s, double x) { return s.t_s < x; });
    if (it == v.begin() || it == v.end()) return false;
    const std::size_t i = static_cast<std::size_t>(it - v.begin());
    const double t0 = v[i - 1].t_s, t1 = v[i].t_s;
    if (t1 - t0 > 2.0) return false;
    const double w = (t - t0) / (t1 - t0);
    p = (1 - w) * cache[i - 1] + w * cache[i];
    return true;
  };
  std::vector<Eigen::Vector2d> c_obs, c_tru;
  std::vector<Ob> obs;
  int missed = 0;
  const double gate = o.gate_deg * kDegToRad;
  for (const auto& fr : data.frames) {
    Eigen::Vector2d po, pt, po_a, po_b, pt_a, pt_b;
    const double h = 0.5;
    if (!interp(data.observer, c_obs, fr.t_s, po) || !interp(data.truth, c_tru, fr.t_s, pt) ||
        !interp(data.observer, c_obs, fr.t_s - h, po_a) || !interp(data.observer, c_obs, fr.t_s + h, po_b) ||
        !interp(data.truth, c_tru, fr.t_s - h, pt_a) || !interp(data.truth, c_tru, fr.t_s + h, pt_b))
      continue;
    auto brg = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return std::atan2(b.y() - a.y(), b.x() - a.x()); };
    const double bt = brg(po, pt);
    const double rate = wrap_pi(brg(po_b, pt_b) - brg(po_a, pt_a)) / (2 * h);
    double best = 1e9;
    for (double b : fr.bearings_rad) {
      const double r = wrap_pi(b - bt);
      if (std::abs(r) < std::abs(best)) best = r;
    }
    if (std::abs(best) > gate) {
      ++missed;
      continue;
    }
    obs.push_back({fr.t_s, best, rate, (pt - po).norm()});
  }
  rep.plots_used = static_cast<int>(obs.size());
  rep.plots_dropped = missed;
  if (obs.size() < 30) throw ConfigError("diagnose uav: fewer than 30 frames with a detection near the truth");

  const double t0 = obs.front().t, span = obs.back().t - t0;
  std::vector<std::pair<std::string, std::vector<Col>>> cands;
  cands.push_back({"bearing_bias", {[](const Ob&) { return 1.0; }}});
  cands.push_back({"bearing_time_offset", {[](const Ob& x) { return -x.rate; }}});
  cands.push_back({"bias_drift", {[t0](const Ob& x) { return x.t - t0; }}});
  std::vector<double> periods;
  for (double P = 4; P <= span / 3; P *= 1.05) periods.push_back(P);
  const double m_family = 4 + 3;

  // robust sigma, outliers, AR(1) from first differences (as in the radar diagnosis)
  std::vector<double> r0;
  for (const auto& x : obs) r0.push_back(x.r);
  const double sigma = 1.4826 * median_abs(r0);  // robust, about zero (the nominal mean)
  for (auto& x : obs) x.outlier = std::abs(x.r) > o.outlier_z * sigma;
  std::vector<std::size_t> use;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (!obs[i].outlier) use.push_back(i);
  double rho = 0, f_ar = 1;
  bool correlated = false;
  {
    std::vector<double> d;
    for (std::size_t i = 1; i < use.size(); ++i) d.push_back(obs[use[i]].r - obs[use[i - 1]].r);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      den += d[i] * d[i];
      if (i) num += d[i] * d[i - 1];
    }
    const double rd = num / den, n = static_cast<double>(d.size());
    rho = std::clamp(1 + 2 * rd, 0.0, 0.99);
    const double z = (rd + 0.5) / std::sqrt(0.5 / n);
    if (0.5 * std::erfc(z / std::sqrt(2.0)) < o.alpha / m_family) {
      correlated = true;
      f_ar = (1 + rho) / (1 - rho);  // variance inflation of regression estimates under AR(1)
    }
  }
  // Forward selection: LR = n ln(RSS0 / RSS1) / f_ar ~ chi2(k).
  std::vector<Col> chosen_cols;
  std::vector<std::string> chosen_names;
  std::vector<double> chosen_par;
  for (;;) {
    const Fit1 base = ols(obs, use, chosen_cols);
    double best_p = 1;
    std::string best_name;
    std::vector<Col> best_cols;
    double best_par = 0;
    auto consider = [&](const std::string& name, const std::vector<Col>& cols, double k, double scan, double par) {
      auto all = chosen_cols;
      all.insert(all.end(), cols.begin(), cols.end());
      const Fit1 f = ols(obs, use, all);
      if (!f.ok) return;
      const double lr = f.n * std::log(base.rss / f.rss) / f_ar;
      const double p = std::min(1.0, chi2_sf(lr, k) * scan);
      if (p < best_p) {
        best_p = p;
        best_name = name;
        best_cols = cols;
        best_par = par;
      }
    };
    for (const auto& [name, cols] : cands)
      if (std::find(chosen_names.begin(), chosen_names.end(), name) == chosen_names.end())
        consider(name, cols, 1, 1, 0);
    if (std::find(chosen_names.begin(), chosen_names.end(), "periodic") == chosen_names.end())
      for (double P : periods)
        consider("periodic",
                 {[P](const Ob& x) { return std::sin(2 * M_PI * x.t / P); },
                  [P](const Ob& x) { return std::cos(2 * M_PI * x.t / P); }},
                 3, static_cast<double>(periods.size()), P);
    if (best_name.empty() || best_p >= o.alpha / m_family) break;
    chosen_names.push_back(best_name);
    chosen_par.push_back(best_par);
    chosen_cols.insert(chosen_cols.end(), best_cols.begin(), best_cols.end());
  }
  const Fit1 fin = ols(obs, use, chosen_cols);
  // Report each chosen effect with its estimate and SE (inflated for AR(1)) and evidence.
  int col = 0;
  for (std::size_t s = 0; s < chosen_names.size(); ++s) {
    EffectResult e;
    e.name = chosen_names[s];
    const int k = e.name == "periodic" ? 2 : 1;
    if (e.name == "periodic") {
      e.params = {"period_s", "amplitude_rad"};
      e.estimate = {chosen_par[s], std::hypot(fin.beta(col), fin.beta(col + 1))};
      e.stderr_ = {0, std::sqrt(f_ar * 0.5 * (fin.cov(col, col) + fin.cov(col + 1, col + 1)))};
    } else {
      e.params = {e.name == "bearing_bias" ? "rad" : e.name == "bearing_time_offset" ? "s" : "rad_per_s"};
      e.estimate = {fin.beta(col)};
      e.stderr_ = {std::sqrt(f_ar * fin.cov(col, col))};
    }
    std::vector<Col> without;
    for (std::size_t j = 0, c = 0; j < chosen_names.size(); ++j) {
      const int kj = chosen_names[j] == "periodic" ? 2 : 1;
      if (j != s)
        for (int q = 0; q < kj; ++q) without.push_back(chosen_cols[c + q]);
      c += kj;
    }
    const Fit1 f0 = ols(obs, use, without);
    e.evidence_lr = fin.n * std::log(f0.rss / fin.rss) / f_ar;
    e.p_value = std::min(1.0, chi2_sf(e.evidence_lr, k + (e.name == "periodic" ? 1 : 0)) *
                                   (e.name == "periodic" ? periods.size() : 1));
    e.delta_bic = e.evidence_lr - k * std::log(fin.n);
    // confounding among the single-column candidates: plain correlation over the used frames
    if (e.name != "periodic")
      for (const auto& [name, cols] : cands) {
        if (name == e.name) continue;
        double sab = 0, saa = 0, sbb = 0;
        for (auto i : use) {
          const double x = chosen_cols[col](obs[i]), y = cols[0](obs[i]);
          sab += x * y;
          saa += x * x;
          sbb += y * y;
        }
        if (saa > 0 && sbb > 0 && std::abs(sab) / std::sqrt(saa * sbb) > o.confound_corr)
          e.confounded_with.push_back(name);
      }
    rep.effects.push_back(e);
    col += k;
  }
  // noise_scale, outliers, correlated_noise
  {
    const double dof = (fin.n - static_cast<double>(chosen_cols.size())) / f_ar;
    const double s2 = fin.rss / (fin.n - static_cast<double>(chosen_cols.size()));
    const double nom = o.sigma_deg * kDegToRad, q = s2 / (nom * nom);
    const double p = 2 * std::min(chi2_sf(dof * q, dof), 1 - chi2_sf(dof * q, dof));
    if (p < o.alpha / m_family) {
      EffectResult e;
      e.name = "noise_scale";
      e.params = {"ratio"};
      e.estimate = {std::sqrt(q)};
      e.stderr_ = {std::sqrt(q) / std::sqrt(2 * dof)};
      e.p_value = p;
      e.evidence_lr = dof * (q - 1 - std::log(q));
      e.note = "fitted bearing sigma " + short_num(std::sqrt(s2) / kDegToRad) + " deg against the nominal " +
               short_num(o.sigma_deg) + " deg";
      rep.effects.push_back(e);
    }
    int n_out = 0;
    for (const auto& x : obs) n_out += x.outlier;
    const double lambda = obs.size() * std::erfc(o.outlier_z / std::sqrt(2.0));
    const double tail = poisson_upper_tail(n_out, lambda);
    if (n_out > 0 && tail < o.alpha / m_family) {
      EffectResult e;
      e.name = "outliers";
      e.params = {"fraction"};
      const double f = static_cast<double>(n_out) / obs.size();
      e.estimate = {f};
      e.stderr_ = {std::sqrt(f * (1 - f) / obs.size())};
      e.p_value = tail;
      e.note = std::to_string(n_out) + " associated detections beyond " + short_num(o.outlier_z) + " robust sigma";
      rep.effects.push_back(e);
    }
    if (correlated) {
      const double dt = span / std::max<std::size_t>(1, obs.size() - 1);
      const double r = std::clamp(rho, 1e-6, 0.99);
      EffectResult e;
      e.name = "correlated_noise";
      e.params = {"tau_s"};
      e.estimate = {-dt / std::log(r)};
      e.stderr_ = {dt / (r * std::log(r) * std::log(r)) * 2 * std::sqrt(0.5 / obs.size())};
      e.p_value = 0;
      e.note = "AR(1) lag-1 coefficient " + short_num(rho) + " from first differences";
      rep.effects.push_back(e);
    }
  }
  // Out-of-sample gain against the GNSS truth: fit on the first split_fraction of the span.
  {
    const double split = t0 + o.split_fraction * span;
    rep.split_time_s = split;
    std::vector<std::size_t> est, scr;
    for (auto i : use) (obs[i].t < split ? est : scr).push_back(i);
    const Fit1 fe = ols(obs, est, chosen_cols);
    if (fe.ok && !scr.empty()) {
      ChannelGain g;
      const double s_nom = std::sqrt(ols(obs, est, {}).rss / est.size()), s_ext = std::sqrt(fe.rss / est.size());
      double a2 = 0, b2 = 0;
      for (auto i : scr) {
        double pred = 0;
        for (std::size_t j = 0; j < chosen_cols.size(); ++j) pred += fe.beta(static_cast<Eigen::Index>(j)) * chosen_cols[j](obs[i]);
        const double r0 = obs[i].r, r1 = obs[i].r - pred;
        a2 += r0 * r0;
        b2 += r1 * r1;
        g.nominal_loglik += -0.5 * (r0 * r0 / (s_nom * s_nom) + std::log(2 * M_PI * s_nom * s_nom));
        g.extended_loglik += -0.5 * (r1 * r1 / (s_ext * s_ext) + std::log(2 * M_PI * s_ext * s_ext));
      }
      g.n = static_cast<int>(scr.size());
      g.nominal_rms = std::sqrt(a2 / scr.size());
      g.extended_rms = std::sqrt(b2 / scr.size());
      rep.gain["bearing_rad"] = g;
    }
    // rows for plots (channel 0 = bearing)
    for (const auto& x : obs) {
      double pred = 0;
      for (std::size_t j = 0; j < chosen_cols.size(); ++j) pred += fin.beta(static_cast<Eigen::Index>(j)) * chosen_cols[j](x);
      rep.rows.push_back({x.t, {x.r, x.rate, x.range}, {0, 0, 0}, {pred, 0, 0}, x.outlier});
    }
  }
  // Unexplained: residual correlation with range, bearing rate and time after the extended model.
  {
    const char* names[3] = {"range", "bearing rate", "time"};
    for (int v = 0; v < 3; ++v) {
      std::vector<double> xs, rs;
      for (auto i : use) {
        double pred = 0;
        for (std::size_t j = 0; j < chosen_cols.size(); ++j) pred += fin.beta(static_cast<Eigen::Index>(j)) * chosen_cols[j](obs[i]);
        xs.push_back(v == 0 ? obs[i].range : v == 1 ? obs[i].rate : obs[i].t);
        rs.push_back(obs[i].r - pred);
      }
      const double c = pearson(xs, rs);
      if (c == 0) continue;
      const double z = std::abs(c) * std::sqrt(xs.size() / f_ar);
      if (std::erfc(z / std::sqrt(2.0)) * 3 < o.alpha)
        rep.unexplained.push_back(std::string("bearing residual correlates with ") + names[v] + " (r = " +
                                  short_num(c) + ") after the extended model");
    }
  }
  return rep;
}

}  // namespace rnav
