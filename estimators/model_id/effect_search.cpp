// Noise first, then forward selection under the identified noise, re-identified until the
// choice settles (effect_search.hpp). The reporting steps are in effect_report.cpp.
#include "effect_search.hpp"

#include "effect_report.hpp"
#include "search_design.hpp"
#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav {

using search_detail::Design;
using Chosen = std::vector<std::pair<std::size_t, std::size_t>>;

std::string Scope::label() const {
  if (sensor.empty() && target.empty()) return "common";
  if (target.empty()) return "sensor " + sensor;
  if (sensor.empty()) return "target " + target;
  return sensor + ":" + target;
}

namespace {

void check_options(const SearchOptions& o) {
  if (!(o.alpha > 0 && o.alpha < 0.5)) throw std::invalid_argument("effect search: alpha must be in (0, 0.5)");
  if (!(o.power > 0.5 && o.power < 1)) throw std::invalid_argument("effect search: power must be in (0.5, 1)");
  if (!(o.confound_corr > 0 && o.confound_corr < 1))
    throw std::invalid_argument("effect search: confound_corr must be in (0, 1)");
  if (o.max_effects < 1 || o.max_rounds < 1) throw std::invalid_argument("effect search: max_effects, max_rounds >= 1");
}

// Channel c's rows of the raw columns X, only the columns that touch the channel.
Eigen::MatrixXd channel_columns(const Design& d, const Eigen::MatrixXd& X, std::size_t c) {
  const auto m = static_cast<Eigen::Index>(d.rows[c].size());
  Eigen::MatrixXd Xc(m, X.cols());
  for (Eigen::Index r = 0; r < m; ++r) Xc.row(r) = X.row(static_cast<Eigen::Index>(d.rows[c][static_cast<std::size_t>(r)]));
  std::vector<Eigen::Index> keep;
  for (Eigen::Index j = 0; j < Xc.cols(); ++j)
    if (!Xc.col(j).isZero(0)) keep.push_back(j);
  Eigen::MatrixXd Xk(m, static_cast<Eigen::Index>(keep.size()));
  for (std::size_t j = 0; j < keep.size(); ++j) Xk.col(static_cast<Eigen::Index>(j)) = Xc.col(keep[j]);
  return Xk;
}

Eigen::VectorXd channel_y(const Design& d, std::size_t c) {
  Eigen::VectorXd e(static_cast<Eigen::Index>(d.rows[c].size()));
  for (std::size_t r = 0; r < d.rows[c].size(); ++r) e(static_cast<Eigen::Index>(r)) = d.pb->y[d.rows[c][r]];
  return e;
}

NoiseIdOptions channel_options(const Problem& p, std::size_t c, const NoiseIdOptions& no) {
  NoiseIdOptions nc = no;
  const Channel& ch = p.channels[c];
  if (ch.nominal_corr_sigma > 0) {
    nc.nominal_share = ch.nominal_share();
    nc.nominal_tau_s = ch.nominal_corr_tau_s;
  }
  return nc;
}

// Each channel's noise, identified with the nuisance and the chosen effects (restricted to the
// channel) as fixed effects, i.e. under the null of the next test. (Identifying it with every
// catalogue entry as a fixed effect, as before, let a dozen slow columns soak up the slow noise
// in REML, the correlated part fell below its AIC threshold, and each column was then tested
// against white noise: 11 of 40 nominal flights named a mean effect under tau = 30 s noise.)
std::vector<NoiseFit> identify_all(const Design& d, const Chosen& chosen, const NoiseIdOptions& no) {
  const Eigen::MatrixXd X = search_detail::raw_model_matrix(d, chosen);
  std::vector<NoiseFit> out;
  for (std::size_t c = 0; c < d.rows.size(); ++c)
    out.push_back(identify_noise(d.times[c], d.gains[c], channel_y(d, c), channel_columns(d, X, c), channel_options(*d.pb, c, no)));
  return out;
}

// A scanned effect (a step, a manoeuvre, a period) is slow where correlated noise is slow: the
// noise identified without it may have absorbed it, and the noise identified with it may be too
// white (the step absorbed the slow noise). Its test is therefore the profile likelihood ratio:
// the ML likelihood maximised over the noise family (NoiseIdOptions::profile_ml: no trend added,
// no AIC threshold) with and without its columns (same frames kept out),
// 2 sum_c [l(with) - l(without)] over the channels it touches. (Testing it under the noise
// re-identified with it alone gave a glide step 2 log LR 61 where the null noise gave 8;
// comparing ML likelihoods at REML-chosen noise parameters, as before, gave 20 where both GLS
// tests gave 5: neither is a likelihood ratio.)
//
// A non-scanned entry's test (fixed): the GLS 2 log LR of its columns given the chosen ones,
// every channel it touches whitened by its noise re-identified (REML, with the trend) with the
// entry's columns added to the null's fixed effects (a Wald-type test: the noise estimated
// under the alternative, so a physical effect the null noise took for a long correlation is
// not lost). Measured on 300 nominal white-noise flights: 1 alarm (0.33 %); the profile
// likelihood ratio used here instead gave 7 (2.3 %: its single further Gauss-Markov part goes
// to the short correlation and leaves slow misfit to the site offset).
class EntryTests {
 public:
  EntryTests(const Design& d, const Chosen& chosen, const std::vector<NoiseFit>& fits, const NoiseIdOptions& no)
      : d_(d), fits_(fits), no_(no), raw_(search_detail::raw_model_matrix(d, chosen)), base_(d.rows.size(), std::nan("")) {
    for (std::size_t c = 0; c < d.rows.size(); ++c) X0c_.push_back(channel_columns(d, raw_, c));
  }
  /// The profile likelihood ratio of scanned entry e at grid point v.
  double scanned(std::size_t e, std::size_t v) {
    NoiseIdOptions pm = no_;
    pm.profile_ml = true;
    auto profile = [&](std::size_t c, const Eigen::MatrixXd& X) {
      return identify_noise(d_.times[c], d_.gains[c], channel_y(d_, c), X, channel_options(*d_.pb, c, pm), &fits_[c].outlier)
          .loglik_ml;
    };
    const Eigen::MatrixXd C = d_.raw_columns(e, v);
    double lr = 0;
    for (std::size_t c = 0; c < d_.rows.size(); ++c) {
      const Eigen::MatrixXd Cc = channel_columns(d_, C, c);
      if (Cc.cols() == 0) continue;  // the entry does not touch this channel
      if (std::isnan(base_[c])) base_[c] = profile(c, X0c_[c]);
      lr += 2 * (profile(c, with(c, Cc)) - base_[c]);
    }
    return lr;
  }
  /// The Wald-type GLS test of non-scanned entry e.
  double fixed(std::size_t e) const {
    const Eigen::MatrixXd C = d_.raw_columns(e, 0);
    std::vector<NoiseParams> np = d_.noise;
    for (std::size_t c = 0; c < d_.rows.size(); ++c) {
      const Eigen::MatrixXd Cc = channel_columns(d_, C, c);
      if (Cc.cols() == 0) continue;  // the entry does not touch this channel: its null noise stays
      NoiseParams q = identify_noise(d_.times[c], d_.gains[c], channel_y(d_, c), with(c, Cc), channel_options(*d_.pb, c, no_),
                                     &fits_[c].outlier)
                          .params;
      q.p_out = 0, q.s_out2 = 0;
      np[c] = q;
    }
    const Eigen::VectorXd y = Eigen::Map<const Eigen::VectorXd>(d_.pb->y.data(), static_cast<Eigen::Index>(d_.pb->size()));
    return search_detail::Projector(d_.whiten_with(raw_, np), d_.whiten_with(y, np), d_.n_used).lr(d_.whiten_with(C, np));
  }

 private:
  // channel c's fixed effects with the entry's columns Cc appended
  Eigen::MatrixXd with(std::size_t c, const Eigen::MatrixXd& Cc) const {
    Eigen::MatrixXd Xc(Cc.rows(), X0c_[c].cols() + Cc.cols());
    Xc << X0c_[c], Cc;
    return Xc;
  }
  const Design& d_;
  const std::vector<NoiseFit>& fits_;
  NoiseIdOptions no_;
  Eigen::MatrixXd raw_;               ///< nuisance and chosen columns, raw
  std::vector<Eigen::MatrixXd> X0c_;  ///< per channel: its fixed-effect columns
  std::vector<double> base_;          ///< per channel: profile l without the entry (when first needed)
};

// Forward selection: the entry with the smallest adjusted log p enters while it is below log
// alpha; each tested by EntryTests (a scanned entry at its best grid point by GLS under the
// null noise).
Chosen forward_select(const Design& d, const SearchOptions& o, double m_family, const std::vector<NoiseFit>& fits) {
  const Problem& p = *d.pb;
  Chosen chosen;
  std::vector<char> taken(p.catalogue.size(), 0);
  const double log_alpha = std::log(o.alpha);
  // the Bonferroni-adjusted log p of entry e's 2 log LR: alpha / m per entry, split over its grid
  auto adjusted_log_p = [&](std::size_t e, double lr) {
    const double k = static_cast<double>(p.catalogue[e].params.size());
    return log_chi2_sf(lr, k) + std::log(static_cast<double>(d.Cw[e].size())) + std::log(m_family);
  };
  for (int step = 0; step < o.max_effects; ++step) {
    const search_detail::Projector P(search_detail::model_matrix(d, chosen), d.yw, d.n_used);
    EntryTests tests(d, chosen, fits, o.noise);
    double best = 0;
    std::pair<std::size_t, std::size_t> arg{0, 0};
    bool any = false;
    for (std::size_t e = 0; e < p.catalogue.size(); ++e) {
      if (taken[e]) continue;
      double lr_v = 0;
      std::size_t v_best = 0;
      for (std::size_t v = 0; v < d.Cw[e].size(); ++v) {
        const double lr = P.lr(d.Cw[e][v]);
        if (lr > lr_v) lr_v = lr, v_best = v;
      }
      if (lr_v <= 0) continue;  // nothing to test (no gain, or inside the model)
      const double lr = p.catalogue[e].scanned() ? tests.scanned(e, v_best) : tests.fixed(e);
      if (!(lr > 0)) continue;
      const double lp = adjusted_log_p(e, lr);
      if (!any || lp < best) best = lp, arg = {e, v_best}, any = true;
    }
    if (!any || best >= log_alpha) break;
    chosen.push_back(arg);
    taken[arg.first] = 1;
  }
  // Backward check: an entry that entered early may no longer be needed once later ones are in
  // (e.g. a site offset that stood in for a drift and a time offset together). The least
  // significant entry, tested against the model without it as it was when it entered, leaves
  // while its adjusted log p is at or above log alpha.
  while (chosen.size() > 1) {
    double worst = -INFINITY;
    std::size_t wi = 0;
    for (std::size_t i = 0; i < chosen.size(); ++i) {
      Chosen rest = chosen;
      rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(i));
      const auto [e, v] = chosen[i];
      EntryTests tests(d, rest, fits, o.noise);
      const double lr = p.catalogue[e].scanned() ? tests.scanned(e, v) : tests.fixed(e);
      const double lp = adjusted_log_p(e, std::max(lr, 0.0));
      if (lp > worst) worst = lp, wi = i;
    }
    if (worst < log_alpha) break;
    chosen.erase(chosen.begin() + static_cast<std::ptrdiff_t>(wi));
  }
  return chosen;
}

}  // namespace

SearchResult search_effects(const Problem& pb, const SearchOptions& o_in) {
  check_options(o_in);
  SearchOptions o = o_in;
  Design d(pb);
  SearchResult res;
  const double n_ch = static_cast<double>(pb.channels.size());
  // The family: every catalogue entry, and three noise tests (scale, correlation, outliers) per channel.
  res.family_size = static_cast<double>(pb.catalogue.size()) + 3 * n_ch;
  res.familywise = "alpha = " + short_num(o.alpha) + " familywise: Bonferroni over " + short_num(res.family_size) +
                   " tests (" + std::to_string(pb.catalogue.size()) + " catalogue entries, each scanned entry split over "
                   "its grid; 3 noise tests per channel x " + std::to_string(pb.channels.size()) + " channels)";
  o.noise.alpha_correlated = o.alpha / res.family_size;

  Chosen chosen;
  std::vector<NoiseFit> fits;
  for (int round = 0; round < o.max_rounds; ++round) {
    fits = identify_all(d, chosen, o.noise);
    std::vector<NoiseParams> np;
    std::vector<std::vector<char>> sk;
    for (const auto& f : fits) {
      NoiseParams q = f.params;
      q.p_out = 0, q.s_out2 = 0;
      np.push_back(q);
      sk.push_back(f.outlier);
    }
    d.set_noise(np, sk);
    const Chosen next = forward_select(d, o, res.family_size, fits);
    const bool settled = next == chosen;
    chosen = next;
    if (settled && round > 0) break;
  }
  search_detail::report(d, o, chosen, fits, res);
  return res;
}

}  // namespace rnav
