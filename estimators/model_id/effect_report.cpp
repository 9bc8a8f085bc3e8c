#include "estimators/model_id/effect_report.hpp"
#include "estimators/model_id/entry_tests.hpp"
#include "estimators/model_id/replication.hpp"

#include "estimators/model_id/drawn_noise.hpp"
#include "estimators/model_id/offset_groups.hpp"
#include "estimators/model_id/parallel_for.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace rnav::search_detail {

namespace {

using Chosen = std::vector<std::pair<std::size_t, std::size_t>>;

Chosen without(const Chosen& c, std::size_t s) {
  Chosen out = c;
  out.erase(out.begin() + static_cast<std::ptrdiff_t>(s));
  return out;
}

// SE of a scanned value from its profile: half the width of {v : LR(v) >= LR_max - 1}, at
// least the grid step / sqrt(12).
double scan_se(const Design& d, const Projector& P, std::size_t e, std::size_t v0) {
  const Candidate& c = d.pb->catalogue[e];
  const double top = P.entry_lr(d, e, v0);
  std::size_t lo = v0, hi = v0;
  while (lo > 0 && P.entry_lr(d, e, lo - 1) >= top - 1) --lo;
  while (hi + 1 < c.scan.size() && P.entry_lr(d, e, hi + 1) >= top - 1) ++hi;
  const double step = c.scan.size() > 1 ? std::abs(c.scan[1] - c.scan[0]) : 0.0;
  return std::max(0.5 * std::abs(c.scan[hi] - c.scan[lo]), step / std::sqrt(12.0));
}

// c's signature for a sentence that names it beside other's: with c's scope where the two read
// the same (two entries of one kind on different targets, each "... of this target").
std::string signature_named(const Candidate& c, const Candidate& other) {
  return c.signature == other.signature ? c.signature + " (" + c.scope.label() + ")" : c.signature;
}

void confounding(const Design& d, const SearchOptions& o, const Chosen& chosen, double m, FoundEffect& fe,
                 std::size_t s) {
  const Problem& p = *d.pb;
  const Chosen rest = without(chosen, s);
  const Projector P = projector_of(d, rest);
  const auto [e, v] = chosen[s];
  const double lr_self = P.entry_lr(d, e, v);
  for (std::size_t f = 0; f < p.catalogue.size(); ++f) {
    if (f == e || p.catalogue[f].scope_only ||
        std::any_of(chosen.begin(), chosen.end(), [&](const auto& c) { return c.first == f; }))
      continue;
    const Rival r = rival(d, P, e, v, f, o.alpha, o.confound_corr, m);
    if (r.same) {
      FoundEffect::Confound cf;
      cf.name = p.catalogue[f].name;
      cf.scope = p.catalogue[f].scope;
      cf.corr = r.corr;
      cf.dlr = lr_self - r.lr;
      cf.entry = f;
      cf.params = p.catalogue[f].params;
      fe.confounded_with.push_back(cf);
    }
  }
  std::sort(fe.confounded_with.begin(), fe.confounded_with.end(),
            [](const auto& a, const auto& b) { return a.dlr < b.dlr; });
  if (fe.confounded_with.size() > 4) fe.confounded_with.resize(4);
  if (!fe.confounded_with.empty()) {
    const auto& c = fe.confounded_with.front();
    const Candidate& other = p.catalogue[c.entry];
    const Candidate& self = p.catalogue[e];
    fe.note += (fe.note.empty() ? "" : "; ") + std::string("explains the same residual here as ") + c.name + " (" +
               c.scope.label() + "; canonical correlation " + short_num(c.corr) + ", 2 log LR difference " +
               short_num(c.dlr) + ")" + (self.is_shape() ? "" : "; named as the physical one-parameter cause") +
               ". Data in which " + signature_named(self, other) + " and " + signature_named(other, self) +
               " vary differently would separate them";
  }
}

// Chosen effect s from the final fit (its columns from col on; col moves past them), with its evidence and confounding.
FoundEffect chosen_effect(const Design& d, const SearchOptions& o, const Chosen& chosen, const std::vector<double>& kept_lr,
                          const Ols& fin, const Eigen::MatrixXd& cov, double m, std::size_t s, Eigen::Index& col) {
  const Problem& p = *d.pb;
  const auto [e, v] = chosen[s];
  const Candidate& c = p.catalogue[e];
  FoundEffect fe;
  fe.name = c.name;
  fe.scope = c.scope;
  fe.params = c.params;
  fe.entry = e;
  fe.variant = v;
  for (std::size_t j = 0; j < c.params.size(); ++j) {
    fe.estimate.push_back(fin.beta(col + static_cast<Eigen::Index>(j)));
    fe.stderr_.push_back(std::sqrt(cov(col + static_cast<Eigen::Index>(j), col + static_cast<Eigen::Index>(j))));
  }
  col += static_cast<Eigen::Index>(c.params.size());
  const Chosen rest = without(chosen, s);
  const Projector P = projector_of(d, rest);
  fe.lr = P.entry_lr(d, e, v);
  const double k = static_cast<double>(c.params.size());
  // log10 of the Bonferroni-adjusted p of a 2 log LR, at most 0 (p = 1)
  auto log10_adjusted = [&](double lr) {
    return std::min(0.0, bonferroni_log_p(lr, k, static_cast<double>(c.variants()), m) / std::log(10.0));
  };
  fe.log10_p = log10_adjusted(fe.lr);
  fe.kept_lr = kept_lr[s];
  fe.kept_log10_p = log10_adjusted(fe.kept_lr);
  fe.delta_bic = fe.lr - (k + (c.scanned() ? 1 : 0)) * std::log(d.n_used);
  if (c.scanned()) {
    fe.scan_param = c.scan_param;
    fe.scan_value = c.scan[v];
    fe.scan_se = scan_se(d, P, e, v);
    fe.note = "scanned over " + std::to_string(c.scan.size()) + " values of " + c.scan_param +
              " (look-elsewhere: its share of alpha is split over them)";
  }
  fe.replication = replication(d, chosen, s);
  confounding(d, o, chosen, m, fe, s);
  return fe;
}

// The detection and separation limits of every non-scanned entry, per parameter.
void detection_limits(const Design& d, const SearchOptions& o, double m, SearchResult& res) {
  // ---- detection limits: each non-scanned entry alone with the nuisance; separation limits:
  // the same given the other non-scanned entry that inflates its SE most (the size at which it
  // is told from that partner with the same probability), z times
  //   SE(e | nuisance, f) = SE(e | nuisance) / sqrt(1 - rho^2), rho its partial correlation with f;
  //   naming limit = 2 z_power SE(e | nuisance, f)  (see SeparationLimit::naming_size) ----
  const Problem& p = *d.pb;
  const Eigen::Index q = p.nuisance.cols();
  const double z_power = normal_upper_quantile(1 - o.power);
  const double z = z_two_sided(o.alpha / m) + z_power;
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  // SE of parameter j of model[0] from its least-squares fit f
  auto se_in = [&](const Ols& f, std::size_t j) {
    if (!f.ok) return nan;
    const auto ix = q + static_cast<Eigen::Index>(j);
    return std::sqrt(f.cov_unscaled(ix, ix) * f.rss / std::max(1.0, f.n - static_cast<double>(f.beta.size())));
  };
  std::vector<std::size_t> entries;
  for (std::size_t e = 0; e < p.catalogue.size(); ++e)
    if (!p.catalogue[e].scanned() && !p.catalogue[e].scope_only) entries.push_back(e);
  // Each entry alone, and the channels its whitened columns touch. Without nuisance columns, two
  // entries touching no common channel have orthogonal columns: the joint fit is block diagonal,
  // so e's (X'X)^-1 is its own, the residual sum of squares drops by what f alone explains
  // (||y||^2 - RSS_f), and the joint rank is the sum of the two. Only pairs sharing a channel
  // (a sensor-wide entry and a target's, two of one target's) need the joint fit.
  std::vector<Ols> alone(p.catalogue.size());
  std::vector<std::vector<char>> touches(p.catalogue.size());
  parallel_for(entries.size(), o.threads, [&](std::size_t i) {
    const std::size_t e = entries[i];
    alone[e] = ols(model_matrix(d, {{e, 0}}), d.yw, d.used);
    const Eigen::MatrixXd& C = d.Cw[e][0];
    touches[e].assign(d.rows.size(), 0);
    for (std::size_t c = 0; c < d.rows.size(); ++c)
      for (std::size_t r : d.rows[c])
        if (!C.row(static_cast<Eigen::Index>(r)).isZero(0)) {
          touches[e][c] = 1;
          break;
        }
  });
  double yy = 0;  // ||y||^2 over the frames used (ols's mask)
  for (Eigen::Index i = 0; i < d.yw.size(); ++i)
    if (d.used[static_cast<std::size_t>(i)]) yy += d.yw(i) * d.yw(i);
  auto share_channel = [&](std::size_t e, std::size_t f) {
    for (std::size_t c = 0; c < touches[e].size(); ++c)
      if (touches[e][c] && touches[f][c]) return true;
    return false;
  };
  // SE of e's parameter j given f (NaN: e inside the span of the nuisance and f)
  auto se_given = [&](std::size_t e, std::size_t f, std::size_t j) {
    if (q > 0 || share_channel(e, f)) return se_in(ols(model_matrix(d, {{e, 0}, {f, 0}}), d.yw, d.used), j);
    const Ols& a = alone[e];
    const Ols& b = alone[f];
    if (!a.ok || !b.ok) return nan;
    const double rss = std::max(0.0, a.rss - (yy - b.rss));
    const double dof = a.n - static_cast<double>(a.beta.size() + b.beta.size());
    return std::sqrt(a.cov_unscaled(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)) * rss / std::max(1.0, dof));
  };
  struct Limits {
    std::map<std::string, double> detection;
    std::map<std::string, SeparationLimit> separation;
  };
  std::vector<Limits> out(entries.size());
  parallel_for(entries.size(), o.threads, [&](std::size_t i) {
    const std::size_t e = entries[i];
    const Candidate& c = p.catalogue[e];
    for (std::size_t j = 0; j < c.params.size(); ++j) {
      const double se = se_in(alone[e], j);
      if (!std::isfinite(se)) continue;
      out[i].detection[c.params[j]] = z * se;
      SeparationLimit worst{z * se, "", 0.0, 2 * z_power * se};
      for (std::size_t f : entries) {
        if (f == e) continue;
        const double se_f = se_given(e, f, j);
        const Candidate& other = p.catalogue[f];
        std::string label = other.name + " (" + other.scope.label();
        for (const auto& pn : other.params) label += "; " + pn;
        label += ")";
        if (!std::isfinite(se_f)) {  // inside the partner's span: no size tells them apart
          worst = {inf, label, 1.0, inf};
          break;
        }
        if (z * se_f > worst.size) worst = {z * se_f, label, std::sqrt(std::max(0.0, 1 - (se / se_f) * (se / se_f))), 2 * z_power * se_f};
      }
      out[i].separation[c.params[j]] = worst;
    }
  });
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const Candidate& c = p.catalogue[entries[i]];
    const std::string key = c.name + "@" + c.scope.label();
    for (const auto& [k, v] : out[i].detection) res.detection_limits[key][k] = v;
    for (const auto& [k, v] : out[i].separation) res.separation_limits[key][k] = v;
  }
}

// The noise findings per channel (res.noise): its scale against the nominal and its correlation.
void noise_findings(const Design& d, const SearchOptions& o, const std::vector<NoiseFit>& fits, double m,
                    SearchResult& res) {
  const Problem& p = *d.pb;
  for (std::size_t ch = 0; ch < d.rows.size(); ++ch) {
    ChannelNoise cn;
    cn.fit = fits[ch];
    const NoiseParams& np = cn.fit.params;
    // The scale of the nominal model's structure (its white and nominal correlated parts) against
    // the nominal variance: 2 log LR = n' (q - 1 - log q), exact when the structure holds (the
    // whitened residuals are then independent). The chosen model's marginal s^2 is not used: a
    // slow component the AIC rule admits has a poorly determined variance. Where a further
    // correlated part was chosen, n' shrinks to the effective size under its lag-one correlation.
    const double qv = cn.fit.s2_nominal / p.channels[ch].nominal_var();
    const auto& t = d.times[ch];
    const double dt = (t.back() - t.front()) / std::max<double>(1, static_cast<double>(t.size()) - 1);
    const double rho1 = np.lambda > 0 ? (1 - np.nom_share) * np.lambda * std::exp(-dt / np.tau_s) : 0.0;
    const double n_eff = std::max(2.0, cn.fit.dof_nominal * (1 - rho1) / (1 + rho1));
    cn.noise_scale = std::sqrt(qv);
    cn.noise_scale_se = cn.noise_scale / std::sqrt(2 * n_eff);
    const double lr = n_eff * (qv - 1 - std::log(qv));
    cn.log10_p_scale = std::min(0.0, bonferroni_log_p(lr, 1, 1, m) / std::log(10.0));
    cn.scale_named = cn.log10_p_scale < std::log10(o.alpha);
    cn.correlated_named = cn.fit.departs_nominal;
    res.noise.push_back(cn);
  }
  drawn_noise(d, o, res);
}

// Whether each channel's outliers are named (res.noise[ch].outliers_named), after out_of_sample.
void name_outliers(const Design& d, const SearchOptions& o, const Chosen& chosen, double m, SearchResult& res) {
  // outliers named: flags in excess of the Gaussian expectation, a positive held-out gain of the
  // heavy-tailed mixture over the identified (coloured) noise model, and isolated flags: gross
  // errors strike single frames (at a rate p a flag has a flagged neighbour with probability
  // about 2 p), while a burst of coloured noise the model underrates flags runs of frames; at
  // most a quarter of the flagged frames may have a flagged neighbour.
  // The count tested against the Gaussian expectation (Poisson, mean expected_false_flags) is
  // that of the flags no noise model within noise_set_q / 2 of the best REML log-likelihood
  // explains (outliers_beyond_noise_set), as every mean effect must pass under each of them:
  // the expectation holds under the true noise model, not under its estimate, and two flags
  // (P = 0.0012 at the expectation 0.05, below alpha / m for m <= 8 tests) came from a
  // Gauss-Markov bearing noise whose tau the fit got wrong. The cost: a gross error within the
  // noise model's uncertainty of the 3.9-sigma threshold is not counted (a 10-sigma one is).
  std::optional<Eigen::MatrixXd> X;  // the raw model, built when a channel's count first needs it
  for (std::size_t ch = 0; ch < res.noise.size(); ++ch) {
    ChannelNoise& cn = res.noise[ch];
    const int flagged = static_cast<int>(d.rows[ch].size()) - cn.fit.n;
    const double lambda = o.noise.expected_false_flags;
    const std::vector<char>& f = cn.fit.outlier;
    int in_runs = 0;
    for (std::size_t i = 0; i < f.size(); ++i)
      in_runs += f[i] && ((i > 0 && f[i - 1]) || (i + 1 < f.size() && f[i + 1]));
    cn.outliers_in_runs = in_runs;
    cn.outliers_beyond_set = flagged;
    const bool count_passes = flagged > 0 && poisson_upper_tail(flagged, lambda) * m < o.alpha;
    if (count_passes && o.noise_set_q > 0 && cn.outlier_gain > 0 && 4 * in_runs <= flagged) {
      // the channel's residuals and fixed-effect columns (those touching it), as identified
      const NoiseIdOptions nc = channel_options(*d.pb, ch, o.noise);
      if (!X) X = raw_model_matrix(d, chosen);
      const Eigen::MatrixXd Xc = channel_columns(d, *X, ch);
      const Eigen::VectorXd y = channel_y(d, ch);
      try {
        const std::vector<char> beyond = outliers_beyond_noise_set(d.times[ch], d.gains[ch], y, Xc, nc, f, o.noise_set_q);
        cn.outliers_beyond_set = static_cast<int>(std::count(beyond.begin(), beyond.end(), 1));
      } catch (const DegenerateSeries&) {
        // the columns span the channel without its flagged frames: no set, the plug-in count stands
      }
    }
    const int counted = cn.outliers_beyond_set;
    cn.outliers_named = counted > 0 && poisson_upper_tail(counted, lambda) * m < o.alpha && cn.outlier_gain > 0 &&
                        4 * in_runs <= flagged;
  }
}

// The covariates a channel's residual under the final model (M beta) still correlates with (res.unexplained).
void unexplained(const Design& d, const SearchOptions& o, const Eigen::MatrixXd& M, const Eigen::VectorXd& beta,
                 SearchResult& res) {
  const Problem& p = *d.pb;
  const Eigen::VectorXd rw = d.yw - M * beta;
  const double tests = std::max(1.0, static_cast<double>(p.covariates.size() * d.rows.size()));
  for (const auto& [name, values] : p.covariates) {
    if (values.size() != p.size()) throw std::invalid_argument("effect search: covariate " + name + " has the wrong size");
    const Eigen::VectorXd xw = d.whiten(Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size())));
    for (std::size_t ch = 0; ch < d.rows.size(); ++ch) {
      std::vector<double> a, b;
      for (auto i : d.rows[ch])
        if (d.used[i]) a.push_back(xw(static_cast<Eigen::Index>(i))), b.push_back(rw(static_cast<Eigen::Index>(i)));
      const double r = pearson(a, b);
      const double z = std::abs(r) * std::sqrt(static_cast<double>(a.size()));
      if (r != 0 && std::erfc(z / std::sqrt(2.0)) * tests < o.alpha)
        res.unexplained.push_back(p.channels[ch].name + " residual correlates with " + name + " (r = " + short_num(r) +
                                  ", after the extended model and its noise model)");
    }
  }
}

// The answer to scope question sq: each alternative's 2 log LR and BIC given the chosen effects outside them.
ScopeAnswer scope_answer(const Design& d, const Chosen& chosen, const ScopeQuestion& sq) {
  ScopeAnswer ans;
  ans.question = sq.question;
  std::vector<std::size_t> family;
  for (const auto& alt : sq.alternatives) family.insert(family.end(), alt.second.begin(), alt.second.end());
  Chosen base;
  for (const auto& c : chosen)
    if (std::find(family.begin(), family.end(), c.first) == family.end()) base.push_back(c);
  const Eigen::MatrixXd B = model_matrix(d, base);
  const Projector P(B, d.yw, d.n_used);
  ScopeAnswer::Alt none{"none", 0, 0, 0};
  ans.alternatives.push_back(none);
  double best = 0;
  ans.supported = "none";
  for (const auto& [label, entries] : sq.alternatives) {
    Chosen add;
    for (auto e : entries) {  // the chosen grid point of a chosen entry, else point 0
      const auto it = std::find_if(chosen.begin(), chosen.end(), [&](const auto& c) { return c.first == e; });
      add.push_back({e, it != chosen.end() ? it->second : 0});
    }
    const Eigen::MatrixXd all = model_matrix(d, add);
    Eigen::MatrixXd C = all.rightCols(all.cols() - d.Nw.cols());
    // keep independent columns only (e.g. a common effect inside per-sensor ones)
    // (columns scaled to unit norm first: their units differ by orders of magnitude)
    Eigen::VectorXd inv_norm(C.cols());
    for (Eigen::Index j = 0; j < C.cols(); ++j) inv_norm(j) = C.col(j).norm() > 0 ? 1.0 / C.col(j).norm() : 1.0;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(C * inv_norm.asDiagonal());
    qr.setThreshold(1e-6);
    if (qr.rank() < C.cols()) C = Eigen::MatrixXd(C * qr.colsPermutation()).leftCols(qr.rank());
    ScopeAnswer::Alt a;
    a.label = label;
    a.k = static_cast<int>(C.cols());
    a.lr = std::max(0.0, P.lr(C));
    a.bic = a.k * std::log(d.n_used) - a.lr;
    if (a.bic < best) best = a.bic, ans.supported = label;
    ans.alternatives.push_back(a);
  }
  return ans;
}

}  // namespace

void report(const Design& d, const SearchOptions& o, const Chosen& chosen, const std::vector<double>& kept_lr,
            const std::vector<NoiseFit>& fits, SearchResult& res) {
  const Problem& p = *d.pb;
  if (kept_lr.size() != chosen.size()) throw std::logic_error("effect search: one kept 2 log LR per chosen effect expected");
  const double m = res.family_size;
  const Eigen::MatrixXd M = model_matrix(d, chosen);
  const Ols fin = ols(M, d.yw, d.used);
  if (!fin.ok) throw std::logic_error("effect search: the chosen model is singular");
  const double scale = fin.rss / std::max(1.0, fin.n - static_cast<double>(M.cols()));
  const Eigen::MatrixXd cov = fin.cov_unscaled * scale;
  const Eigen::MatrixXd R = raw_model_matrix(d, chosen);
  const Eigen::Index q = p.nuisance.cols();
  res.nuisance_beta = fin.beta.head(q);
  // (No nuisance and no effect: cov is 0 x 0, whose diagonal() Eigen may not even take.)
  res.nuisance_se = q > 0 ? Eigen::VectorXd(cov.diagonal().head(q).cwiseSqrt()) : Eigen::VectorXd();
  res.nuisance_fit = q > 0 ? Eigen::VectorXd(R.leftCols(q) * fin.beta.head(q)) : Eigen::VectorXd::Zero(R.rows());
  res.effect_fit = R.rightCols(R.cols() - q) * fin.beta.tail(R.cols() - q);
  res.nominal_fit = Eigen::VectorXd::Zero(R.rows());
  if (q > 0) {
    const Ols f0 = ols(d.Nw, d.yw, d.used, true);
    if (f0.ok) res.nominal_fit = p.nuisance * f0.beta;
  }

  // ---- the chosen effects ----
  Eigen::Index col = q;
  for (std::size_t s = 0; s < chosen.size(); ++s)
    res.effects.push_back(chosen_effect(d, o, chosen, kept_lr, fin, cov, m, s, col));
  if (o.effects_only) return;

  detection_limits(d, o, m, res);

  // ---- noise findings per channel ----
  noise_findings(d, o, fits, m, res);
  offset_groups(d, o, chosen, res);

  if (o.score_holdout) out_of_sample(d, o, res);
  name_outliers(d, o, chosen, m, res);

  // ---- unexplained: whitened residual against whitened covariates ----
  unexplained(d, o, M, fin.beta, res);

  // ---- scope questions ----
  for (const auto& sq : p.scope_questions) res.scopes.push_back(scope_answer(d, chosen, sq));
}

}  // namespace rnav::search_detail
