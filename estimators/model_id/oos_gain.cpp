// Out-of-sample gain: the nominal model (nuisance only, the nominal white sigma) and the
// extended one (nuisance + the named effects; its noise the nominal one unless a noise finding
// was named, then identified on the estimation frames' residuals) are fitted on the estimation frames and scored on the held-out frames:
// residual RMS, and the one-step-ahead predictive log-likelihood (every frame conditions the
// later ones; only held-out frames are summed). The outlier mixture is kept for a channel only
// if it raises that held-out likelihood.
#include "estimators/model_id/effect_report.hpp"

#include <cmath>

namespace rnav::search_detail {

namespace {
// The rows of M where mask is set.
Eigen::MatrixXd rows_where(const Eigen::MatrixXd& M, const std::vector<char>& mask) {
  Eigen::Index n = 0;
  for (char m : mask) n += m != 0;
  Eigen::MatrixXd out(n, M.cols());
  for (Eigen::Index i = 0, r = 0; i < M.rows(); ++i)
    if (mask[static_cast<std::size_t>(i)]) out.row(r++) = M.row(i);
  return out;
}

// How well the window determines an effect where it is used: the smaller of
//  - the largest |estimate / SE| of its k coefficients from col (is it there at all?), and
//  - its predicted contribution on the held-out frames against that prediction's own standard
//    error, both RMS over those frames (whitened): z_h = sqrt(sum (C_h b)^2 / sum diag(C_h V C_h')),
//    V = the coefficients' covariance (for one parameter exactly |estimate / SE|). Only the
//    held-out frames' regressors enter (their geometry), never their residuals. A
//    multi-parameter effect with a part the window leaves open (an along-hull offset on one
//    straight leg, SE 7.7 m, extrapolated through a turn) is thus not extrapolated: its
//    prediction would be mostly its uncertainty.
double determined_z(const Ols& f, Eigen::Index col, Eigen::Index k, const Eigen::MatrixXd& C_held) {
  const double scale = f.rss / std::max(1.0, f.n - static_cast<double>(f.beta.size()));
  double z = 0;
  for (Eigen::Index j = col; j < col + k; ++j) z = std::max(z, std::abs(f.beta(j)) / std::sqrt(f.cov_unscaled(j, j) * scale));
  if (C_held.rows() == 0) return z;
  const Eigen::VectorXd b = f.beta.segment(col, k);
  const Eigen::MatrixXd V = f.cov_unscaled.block(col, col, k, k) * scale;
  const double signal = (C_held * b).squaredNorm();
  const double var = (C_held * V).cwiseProduct(C_held).sum();
  return var > 0 ? std::min(z, std::sqrt(signal / var)) : z;
}

// The columns of effect c (entry, grid point) on the held-out frames.
Eigen::MatrixXd held_cols(const Design& d, const std::pair<std::size_t, std::size_t>& c, const std::vector<char>& held) {
  return rows_where(d.Cw[c.first][c.second], held);
}

// The chosen effects the estimation window `est` determines, taken in the order they were
// named (out_of_sample says when one is left out).
std::vector<std::pair<std::size_t, std::size_t>> determined_in_window(
    const Design& d, const SearchOptions& o, const std::vector<std::pair<std::size_t, std::size_t>>& chosen,
    const std::vector<char>& est, const std::vector<char>& held) {
  const Problem& p = *d.pb;
  const Eigen::Index q = p.nuisance.cols();
  const Eigen::MatrixXd Nw_est = rows_where(d.Nw, est);
  std::vector<std::pair<std::size_t, std::size_t>> kept;
  for (const auto& c : chosen) {
    const Eigen::MatrixXd& C = d.Cw[c.first][c.second];
    double in = 0;
    for (Eigen::Index i = 0; i < C.rows(); ++i)
      if (est[static_cast<std::size_t>(i)]) in += C.row(i).squaredNorm();
    if (!(in > 1e-12 * C.squaredNorm())) continue;  // absent from the window
    std::vector<std::pair<std::size_t, std::size_t>> trial = kept;
    trial.push_back(c);
    const Eigen::MatrixXd Mt = model_matrix(d, trial);  // [Nw | kept | C]
    if (!kept.empty() &&
        canonical_corr(Nw_est, rows_where(C, est), rows_where(Mt.middleCols(q, Mt.cols() - q - C.cols()), est)) > o.confound_corr)
      continue;
    const Ols f = ols(Mt, d.yw, est);
    if (!f.ok) continue;
    const auto k = static_cast<Eigen::Index>(p.catalogue[c.first].params.size());
    if (determined_z(f, f.beta.size() - k, k, held_cols(d, c, held)) >= o.holdout_min_z) kept = trial;
  }
  return kept;
}

// Channel c's out-of-sample gain into res.gain[c] (residual RMS and predictive log-likelihood
// of the nominal prediction pred0 and the extended pred1 on its held-out frames) and its
// outlier mixture's gain into res.noise[c].
void score_channel(const Design& d, const NoiseIdOptions& no, std::size_t c, const Eigen::VectorXd& pred0,
                   const Eigen::VectorXd& pred1, SearchResult& res) {
  const Problem& p = *d.pb;
  const Eigen::Map<const Eigen::VectorXd> y(p.y.data(), static_cast<Eigen::Index>(p.size()));
  const auto& rows = d.rows[c];
  std::vector<double> r0, r1, t, r1_est, t_est, h_est;
  const std::vector<double>& h = d.gains[c];
  std::vector<char> score;
  for (auto i : rows) {
    const auto ii = static_cast<Eigen::Index>(i);
    r0.push_back(y(ii) - pred0(ii));
    r1.push_back(y(ii) - pred1(ii));
    t.push_back(p.t_s[i]);
    score.push_back(!p.estimation[i]);
    if (p.estimation[i]) {
      r1_est.push_back(r1.back()), t_est.push_back(p.t_s[i]);
      if (!h.empty()) h_est.push_back(h[t.size() - 1]);
    }
  }
  SeriesGain& g = res.gain[c];
  double a = 0, b = 0;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (score[k] && d.used[rows[k]]) a += r0[k] * r0[k], b += r1[k] * r1[k], ++g.n;
  if (g.n == 0 || r1_est.size() < 10) return;
  g.nominal_rms = std::sqrt(a / g.n);
  g.extended_rms = std::sqrt(b / g.n);
  NoiseParams nom;
  nom.s2 = p.channels[c].nominal_var();
  if (p.channels[c].nominal_corr_sigma > 0) {
    nom.nom_share = p.channels[c].nominal_share();
    nom.nom_tau_s = p.channels[c].nominal_corr_tau_s;
  }
  g.nominal_loglik = predictive_loglik(t, h, r0, nom, score);
  // The extended model's noise: the nominal one, unless the search named a noise finding for
  // this channel (noise_scale or correlated_noise): then the model identified on the
  // estimation frames' extended residuals. An outlier mixture (flags on those frames) on top.
  NoiseIdOptions nc = no;
  nc.nominal_share = nom.nom_share, nc.nominal_tau_s = nom.nom_tau_s;
  const NoiseFit nf = identify_noise(t_est, h_est, Eigen::Map<const Eigen::VectorXd>(r1_est.data(), static_cast<Eigen::Index>(r1_est.size())),
                                     Eigen::MatrixXd(static_cast<Eigen::Index>(r1_est.size()), 0), nc);
  const bool noise_named = res.noise[c].scale_named || res.noise[c].correlated_named;
  NoiseParams gauss = noise_named ? nf.params : nom;
  gauss.p_out = 0, gauss.s_out2 = 0;
  NoiseParams mix = gauss;
  mix.p_out = nf.params.p_out, mix.s_out2 = nf.params.s_out2;
  const double l_gauss = predictive_loglik(t, h, r1, gauss, score);
  const double l_mix = mix.p_out > 0 ? predictive_loglik(t, h, r1, mix, score) : l_gauss;
  res.noise[c].outlier_gain = l_mix - l_gauss;
  g.extended_loglik = std::max(l_gauss, l_mix);
}
}  // namespace

void out_of_sample(const Design& d, const SearchOptions& o, SearchResult& res) {
  const Problem& p = *d.pb;
  std::vector<std::pair<std::size_t, std::size_t>> chosen;
  for (const auto& e : res.effects) chosen.push_back({e.entry, e.variant});
  const auto n = static_cast<Eigen::Index>(p.size());
  std::vector<char> est(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) est[i] = p.estimation[i] && d.used[i];
  const Eigen::Index q = p.nuisance.cols();
  // nominal: nuisance only
  Eigen::VectorXd pred0 = Eigen::VectorXd::Zero(n);
  res.nominal_oos_beta = Eigen::VectorXd::Zero(q);
  if (q > 0) {
    const Ols f0 = ols(d.Nw, d.yw, est, true);
    if (f0.ok) pred0 = p.nuisance * f0.beta, res.nominal_oos_beta = f0.beta;
  }
  res.extended_oos_beta = res.nominal_oos_beta;
  // extended: the chosen effects refitted on the window, taken in the order they were named.
  // An effect is left out when the window does not determine it: absent from the window (a step
  // after the split), its columns confounded there with those kept before it (canonical
  // correlation above confound_corr given the nuisance and them: a pair the window cannot
  // separate, e.g. an along-hull offset and a clock offset on one straight leg, would be
  // extrapolated as a large difference of two large estimates), or determined_z below
  // holdout_min_z given them. The kept set is then refitted (dropping any that fell below).
  std::vector<char> held(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) held[i] = !p.estimation[i] && d.used[i];
  std::vector<std::pair<std::size_t, std::size_t>> kept = determined_in_window(d, o, chosen, est, held);
  Eigen::VectorXd pred1 = pred0;
  for (std::size_t pass = 0; pass <= chosen.size(); ++pass) {
    const Eigen::MatrixXd Mw = model_matrix(d, kept);
    if (Mw.cols() == 0) break;
    const Ols f1 = ols(Mw, d.yw, est);
    std::size_t weakest = kept.size();
    double weakest_z = o.holdout_min_z;
    Eigen::Index col = q;
    for (std::size_t s = 0; s < kept.size(); ++s) {
      const auto k = static_cast<Eigen::Index>(p.catalogue[kept[s].first].params.size());
      const double z = f1.ok ? determined_z(f1, col, k, held_cols(d, kept[s], held)) : 0.0;
      if (z < weakest_z || !f1.ok) weakest_z = z, weakest = s;  // singular: drop the latest chosen
      col += k;
    }
    if (f1.ok && weakest == kept.size()) {
      pred1 = raw_model_matrix(d, kept) * f1.beta;
      res.extended_oos_beta = f1.beta;
      const double scale = f1.rss / std::max(1.0, f1.n - static_cast<double>(f1.beta.size()));
      res.extended_oos_se = (f1.cov_unscaled.diagonal() * scale).cwiseSqrt();
      res.holdout_entries = kept;
      for (const auto& k : kept)
        res.holdout_effects.push_back(p.catalogue[k.first].name + "@" + p.catalogue[k.first].scope.label());
      break;
    }
    kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(weakest == kept.size() ? kept.size() - 1 : weakest));
  }
  res.nominal_oos = pred0;
  res.extended_oos = pred1;
  res.gain.assign(d.rows.size(), SeriesGain{});
  for (std::size_t c = 0; c < d.rows.size(); ++c) score_channel(d, o.noise, c, pred0, pred1, res);
}

}  // namespace rnav::search_detail
