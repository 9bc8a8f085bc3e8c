// Out-of-sample gain. The whole search (noise identification, selection, fit) is rerun on the
// estimation frames alone; its model predicts the held-out frames. The nominal model is the
// nuisance alone, fitted on the same frames, with the nominal white sigma. Scores per channel:
// held-out residual RMS, and the one-step-ahead predictive log-likelihood (every frame
// conditions the later ones; only held-out frames are summed) under the nominal noise and under
// the noise model identified on the estimation frames' extended residuals. The outlier mixture
// counts for a channel only if it raises that held-out likelihood.
#include "effect_report.hpp"

#include <cmath>

namespace rnav::search_detail {

namespace {
// The problem restricted to its estimation frames (channels with too few frames dropped);
// map: sub observation -> full observation.
Problem restrict_to_estimation(const Problem& p, std::vector<std::size_t>& map) {
  std::vector<int> count(p.channels.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) count[static_cast<std::size_t>(p.channel[i])] += p.estimation[i];
  Problem s;
  std::vector<int> new_index(p.channels.size(), -1);
  for (std::size_t c = 0; c < p.channels.size(); ++c)
    if (count[c] >= 20) new_index[c] = static_cast<int>(s.channels.size()), s.channels.push_back(p.channels[c]);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int c = new_index[static_cast<std::size_t>(p.channel[i])];
    if (!p.estimation[i] || c < 0) continue;
    map.push_back(i);
    s.channel.push_back(c);
    s.t_s.push_back(p.t_s[i]);
    s.y.push_back(p.y[i]);
    s.estimation.push_back(1);
  }
  const auto n = static_cast<Eigen::Index>(map.size());
  s.nuisance = Eigen::MatrixXd(n, p.nuisance.cols());
  for (Eigen::Index r = 0; r < n; ++r) s.nuisance.row(r) = p.nuisance.row(static_cast<Eigen::Index>(map[static_cast<std::size_t>(r)]));
  s.nuisance_names = p.nuisance_names;
  for (const auto& c : p.catalogue) {
    Candidate k = c;
    const auto full = c.columns;
    const auto m = map;
    k.columns = [full, m](std::size_t v) {
      const Eigen::MatrixXd C = full(v);
      Eigen::MatrixXd out(static_cast<Eigen::Index>(m.size()), C.cols());
      for (std::size_t r = 0; r < m.size(); ++r) out.row(static_cast<Eigen::Index>(r)) = C.row(static_cast<Eigen::Index>(m[r]));
      return out;
    };
    s.catalogue.push_back(k);
  }
  return s;
}
}  // namespace

void out_of_sample(const Design& d, const SearchOptions& o, SearchResult& res) {
  const Problem& p = *d.pb;
  const auto n = static_cast<Eigen::Index>(p.size());
  const Eigen::Map<const Eigen::VectorXd> y(p.y.data(), n);
  res.nominal_oos = Eigen::VectorXd::Zero(n);
  res.extended_oos = Eigen::VectorXd::Zero(n);
  res.gain.assign(d.rows.size(), SeriesGain{});
  std::vector<std::size_t> map;
  const Problem sub = restrict_to_estimation(p, map);
  if (sub.channels.empty()) return;
  SearchOptions so = o;
  so.score_holdout = false;
  SearchResult rs;
  try {
    rs = search_effects(sub, so);
  } catch (const std::invalid_argument&) {
    return;  // the window alone is too small to pose the problem: no gain reported
  }
  // nominal: the nuisance alone on the window
  if (p.nuisance.cols() > 0) {
    const Design ds(sub);
    Ols f0 = ols(sub.nuisance, Eigen::Map<const Eigen::VectorXd>(sub.y.data(), static_cast<Eigen::Index>(sub.size())));
    if (f0.ok) res.nominal_oos = p.nuisance * f0.beta;
  }
  res.extended_oos = p.nuisance.cols() > 0 ? Eigen::VectorXd(p.nuisance * rs.nuisance_beta) : Eigen::VectorXd::Zero(n);
  for (const auto& e : rs.effects) {
    const Eigen::MatrixXd C = d.raw_columns(e.entry, e.variant);
    for (std::size_t j = 0; j < e.estimate.size(); ++j) res.extended_oos += C.col(static_cast<Eigen::Index>(j)) * e.estimate[j];
    res.holdout_effects.push_back(e.name + "@" + e.scope.label());
  }
  const Eigen::VectorXd& pred0 = res.nominal_oos;
  const Eigen::VectorXd& pred1 = res.extended_oos;
  for (std::size_t c = 0; c < d.rows.size(); ++c) {
    const auto& rows = d.rows[c];
    std::vector<double> r0, r1, t, r1_est, t_est;
    std::vector<char> score;
    for (auto i : rows) {
      const auto ii = static_cast<Eigen::Index>(i);
      r0.push_back(y(ii) - pred0(ii));
      r1.push_back(y(ii) - pred1(ii));
      t.push_back(p.t_s[i]);
      score.push_back(!p.estimation[i]);
      if (p.estimation[i]) r1_est.push_back(r1.back()), t_est.push_back(p.t_s[i]);
    }
    SeriesGain& g = res.gain[c];
    double a = 0, b = 0;
    for (std::size_t k = 0; k < rows.size(); ++k)
      if (score[k] && d.used[rows[k]]) a += r0[k] * r0[k], b += r1[k] * r1[k], ++g.n;
    if (g.n == 0 || r1_est.size() < 20) continue;
    g.nominal_rms = std::sqrt(a / g.n);
    g.extended_rms = std::sqrt(b / g.n);
    NoiseParams nom;
    nom.s2 = p.channels[c].nominal_sigma * p.channels[c].nominal_sigma;
    g.nominal_loglik = predictive_loglik(t, r0, nom, score);
    const NoiseFit nf = identify_noise(t_est, Eigen::Map<const Eigen::VectorXd>(r1_est.data(), static_cast<Eigen::Index>(r1_est.size())),
                                       Eigen::MatrixXd(static_cast<Eigen::Index>(r1_est.size()), 0), o.noise);
    NoiseParams gauss = nf.params;
    gauss.p_out = 0, gauss.s_out2 = 0;
    const double l_gauss = predictive_loglik(t, r1, gauss, score);
    const double l_mix = nf.params.p_out > 0 ? predictive_loglik(t, r1, nf.params, score) : l_gauss;
    res.noise[c].outlier_gain = l_mix - l_gauss;
    g.extended_loglik = std::max(l_gauss, l_mix);
  }
}

}  // namespace rnav::search_detail
